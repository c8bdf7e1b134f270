//! The mmCIF side of loading: only the first data block's `_atom_site`
//! loop is handed to `pdbtbx` (it panics on some other categories, e.g. a
//! `_symmetry` block without `Int_Tables_number`, as in 3NZD), with the
//! original line of each of its lines kept, so that a row `pdbtbx` refuses
//! (its errors carry no usable line) can be named by its line in the file.

use std::collections::HashMap;

/// The first data block's `_atom_site` loop alone, as mmCIF text, with the
/// 1-based line of the original text each of its lines came from; or `None`
/// when it cannot be cut out simply (no such loop, or a `;` text field in it),
/// in which case the whole text goes to `pdbtbx`.
pub(super) fn mmcif_atom_site_only(text: &str) -> Option<(String, Vec<usize>)> {
    let mut lines = text.lines().map(str::trim).enumerate();
    let (data_at, data) = lines.by_ref().find(|(_, l)| l.starts_with("data_"))?;
    let mut out = String::with_capacity(text.len() / 2);
    let mut from = vec![data_at + 1, data_at + 1];
    out.push_str(data);
    out.push_str("\nloop_\n");
    let mut in_loop = false;
    let mut header = false;
    for (at, line) in lines {
        let lower_start = |p: &str| {
            line.get(..p.len())
                .is_some_and(|s| s.eq_ignore_ascii_case(p))
        };
        if !in_loop {
            if lower_start("data_") {
                return None;
            }
            if line.eq_ignore_ascii_case("loop_") {
                in_loop = true;
                header = true;
                from[1] = at + 1;
            }
            continue;
        }
        if header {
            if let Some(name) = column_name(line) {
                // CIF tags are case-insensitive; `pdbtbx` reads them as
                // the dictionary spells them.
                out.push_str("_atom_site.");
                out.push_str(canonical_column(name));
                out.push('\n');
                from.push(at + 1);
                continue;
            }
            if !out.ends_with("loop_\n") {
                header = false;
            } else {
                // Another category's loop: look for the next one.
                in_loop = line.eq_ignore_ascii_case("loop_");
                if in_loop {
                    from[1] = at + 1;
                }
                continue;
            }
        }
        if line.starts_with('_')
            || line.starts_with('#')
            || lower_start("loop_")
            || lower_start("data_")
            || lower_start("stop_")
            || lower_start("save_")
            || lower_start("global_")
        {
            break;
        }
        if line.starts_with(';') {
            return None;
        }
        out.push_str(line);
        out.push('\n');
        from.push(at + 1);
    }
    if out.ends_with("loop_\n") {
        None
    } else {
        Some((out, from))
    }
}

/// The column name of an `_atom_site` tag line (the tag's case aside), or
/// `None` for any other line.
fn column_name(line: &str) -> Option<&str> {
    const PREFIX: &str = "_atom_site.";
    let head = line.get(..PREFIX.len())?;
    head.eq_ignore_ascii_case(PREFIX)
        .then(|| line[PREFIX.len()..].trim())
}

/// The `_atom_site` items `pdbtbx` reads, spelled as the mmCIF dictionary
/// does (it matches them case by case).
const PDBTBX_COLUMNS: [&str; 18] = [
    "group_PDB",
    "id",
    "type_symbol",
    "label_atom_id",
    "label_alt_id",
    "label_comp_id",
    "label_asym_id",
    "label_seq_id",
    "pdbx_PDB_ins_code",
    "Cartn_x",
    "Cartn_y",
    "Cartn_z",
    "occupancy",
    "B_iso_or_equiv",
    "pdbx_formal_charge",
    "auth_seq_id",
    "auth_asym_id",
    "pdbx_PDB_model_num",
];

/// `name` as the dictionary spells it, when it is an item `pdbtbx` reads.
fn canonical_column(name: &str) -> &str {
    PDBTBX_COLUMNS
        .into_iter()
        .find(|c| c.eq_ignore_ascii_case(name))
        .unwrap_or(name)
}

/// A cut-out `_atom_site` loop ([`mmcif_atom_site_only`]: `data_`, `loop_`,
/// the column names, then the rows) as a table: its column names, and its
/// rows as they are read, each line's index in the cut-out with its values
/// (rows one per line, as every mmCIF writer puts them).
fn atom_site_table(cut: &str) -> (Vec<&str>, impl Iterator<Item = (usize, Vec<&str>)>) {
    let mut lines = cut.lines().enumerate().skip(2).peekable();
    let mut columns = Vec::new();
    while let Some(name) = lines.peek().and_then(|(_, l)| column_name(l)) {
        columns.push(name);
        lines.next();
    }
    (columns, lines.map(|(k, line)| (k, cif_values(line))))
}

/// The index of column `name` (case aside) among `columns`.
fn column(columns: &[&str], name: &str) -> Option<usize> {
    columns.iter().position(|c| c.eq_ignore_ascii_case(name))
}

/// The values of one line of CIF data: whitespace-separated, a value that
/// opens with a quote running to the same quote followed by a blank (or the
/// line's end), a `#` outside quotes starting a comment.
pub(super) fn cif_values(line: &str) -> Vec<&str> {
    let bytes = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if bytes[i] == b'#' {
            break;
        }
        let start = i;
        if bytes[i] == b'\'' || bytes[i] == b'"' {
            let quote = bytes[i];
            i += 1;
            while i < bytes.len()
                && !(bytes[i] == quote && bytes.get(i + 1).is_none_or(|b| b.is_ascii_whitespace()))
            {
                i += 1;
            }
            i = (i + 1).min(bytes.len());
        } else {
            while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
                i += 1;
            }
        }
        out.push(line.get(start..i).unwrap_or_default());
    }
    out
}

/// [`super::records::unknown_elements_pdb`] for a cut-out `_atom_site` loop
/// ([`mmcif_atom_site_only`]): its `type_symbol` values by `id`, for rows
/// one per line.
pub(super) fn unknown_elements_cif(cut: &str) -> HashMap<usize, String> {
    let mut out = HashMap::new();
    let (columns, rows) = atom_site_table(cut);
    let (Some(t), Some(i)) = (column(&columns, "type_symbol"), column(&columns, "id")) else {
        return out;
    };
    for (_, values) in rows.filter(|(_, v)| v.len() == columns.len()) {
        let symbol = values[t].trim_matches(['\'', '"']);
        if !matches!(symbol, "" | "." | "?")
            && pdbtbx::Element::from_symbol(symbol).is_none()
            && let Ok(serial) = values[i].parse()
        {
            out.entry(serial).or_insert_with(|| symbol.to_string());
        }
    }
    out
}

/// What is wrong with a cut-out `_atom_site` loop ([`mmcif_atom_site_only`])
/// that `pdbtbx` refused, said with the original line: a row with the wrong
/// number of values (when rows are one per line, as every mmCIF writer puts
/// them), or a coordinate that is not a number. `None` when neither is found.
pub(super) fn diagnose_atom_site(cut: &str, from: &[usize]) -> Option<(usize, String)> {
    let (columns, rows) = atom_site_table(cut);
    let rows: Vec<(usize, Vec<&str>)> = rows
        .filter(|(_, v)| !v.is_empty())
        .map(|(k, v)| (from.get(k).copied().unwrap_or(0), v))
        .collect();
    let n = columns.len();
    let full = rows.iter().filter(|(_, v)| v.len() == n).count();
    if n > 0
        && 2 * full >= rows.len()
        && let Some((at, v)) = rows.iter().find(|(_, v)| v.len() != n)
    {
        return Some((
            *at,
            format!(
                "this _atom_site row has {} values; the loop has {n} columns",
                v.len()
            ),
        ));
    }
    let id = column(&columns, "id");
    for axis in ["Cartn_x", "Cartn_y", "Cartn_z"] {
        let Some(c) = column(&columns, axis) else {
            return Some((
                from.get(1).copied().unwrap_or(0),
                format!("the _atom_site loop has no {axis} column"),
            ));
        };
        for (at, v) in rows.iter().filter(|(_, v)| v.len() == n) {
            let value = v[c];
            if value.parse::<f64>().is_err() {
                let atom = id.map_or(String::new(), |i| format!(" of atom {}", v[i]));
                return Some((*at, format!("{axis}{atom} is not a number: {value:?}")));
            }
        }
    }
    None
}

/// The original line of atom `serial`'s row in a cut-out `_atom_site` loop
/// ([`mmcif_atom_site_only`], `from` its lines' original lines), for rows
/// one per line; `None` when no such row is found.
pub(super) fn atom_site_line(cut: &str, from: &[usize], serial: usize) -> Option<usize> {
    let (columns, mut rows) = atom_site_table(cut);
    let id = column(&columns, "id")?;
    let (k, _) = rows.find(|(_, v)| v.len() == columns.len() && v[id].parse() == Ok(serial))?;
    from.get(k).copied()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn atom_site_loop_is_cut_out() {
        let text = "data_X\n#\nloop_\n_cell.a\n1\n#\nloop_\n_atom_site.id\n_atom_site.x\n1 2.0\n2 3.0\n#\n_other.a 1\n";
        let (cut, from) = mmcif_atom_site_only(text).unwrap();
        assert_eq!(
            cut,
            "data_X\nloop_\n_atom_site.id\n_atom_site.x\n1 2.0\n2 3.0\n"
        );
        // The original line of each line of the cut-out.
        assert_eq!(from, [1, 7, 8, 9, 10, 11]);
        assert!(mmcif_atom_site_only("data_X\nloop_\n_cell.a\n1\n").is_none());
    }

    #[test]
    fn an_atoms_row_is_found_by_its_id() {
        let text = "data_X\n#\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.x\n\
                    ATOM 1 2.0\nATOM 12 '3.0'\nATOM 2 a b\n#\n";
        let (cut, from) = mmcif_atom_site_only(text).unwrap();
        assert_eq!(atom_site_line(&cut, &from, 12), Some(8));
        // A row's value count must match the columns, as `pdbtbx` reads it.
        assert_eq!(atom_site_line(&cut, &from, 2), None);
        assert_eq!(atom_site_line(&cut, &from, 3), None);
        let no_id = "data_X\nloop_\n_atom_site.group_PDB\n_atom_site.x\nATOM 1\n";
        let (cut, from) = mmcif_atom_site_only(no_id).unwrap();
        assert_eq!(atom_site_line(&cut, &from, 1), None);
    }

    #[test]
    fn cif_values_keep_quoted_values_whole() {
        assert_eq!(
            cif_values("ATOM 1 O \"O5'\" . 'A B' 1.0 # note"),
            ["ATOM", "1", "O", "\"O5'\"", ".", "'A B'", "1.0"]
        );
        assert_eq!(cif_values("  "), Vec::<&str>::new());
    }
}
