//! The mmCIF side of loading: a CIF tokenizer that reads the first data
//! block line by line and keeps two categories, `_atom_site` (the atoms)
//! and `_struct_conn` (the bonds between residues), as loops or as single
//! items; every other category is read past without being kept.
//!
//! Tokens follow CIF 1.1: whitespace-separated values, a value opening
//! with a quote running to the same quote followed by a blank or the line's
//! end, `#` outside quotes opening a comment, a line opening with `;` a text
//! field that runs to the next such line, and the reserved words `data_`,
//! `loop_`, `save_`, `global_`, `stop_`. Tags are matched whatever their
//! case. `?` and `.` (unquoted) mean a value unknown or not applicable.
//!
//! An `_atom_site` row gives the atom: `group_PDB` (ATOM or HETATM),
//! `id`, `type_symbol`, `label_atom_id`, `label_alt_id`, `label_comp_id`,
//! the author's chain and residue number where given (`auth_asym_id`,
//! `auth_seq_id`, else the label ones), `pdbx_PDB_ins_code`, `Cartn_x/y/z`,
//! `occupancy` and `pdbx_PDB_model_num` (rows of models other than the
//! first row's are passed over). Every problem names the line and column
//! of the value: a row with too few or too many values (where rows are
//! one per line, as every mmCIF writer puts them), a coordinate that is not
//! a number, a missing column the atoms need.

use std::io::Read;

use glam::DVec3;

use super::bonds::{AtomRef, NamedBond};
use super::guess::guess_from_name;
use super::{Raw, ascii_line, check_position, element_label, line_error};
use crate::model::label::{AtomName, ChainId, ElementSymbol, InsertionCode, ResidueName};
use crate::model::{AtomInfo, BondOrder, Label, LoadError};
use crate::text::{LineReader, excerpt};

/// Longest text field kept, bytes; a longer one is read past, and refused
/// only where a kept category wants its value.
const MAX_TEXT_FIELD: usize = 4096;

/// At most this many warnings about `struct_conn` rows are given one by one.
const MAX_BOND_WARNINGS: usize = 5;

/// Reads the atoms of mmCIF text's first model (of its first data block)
/// and its `struct_conn` bonds.
///
/// # Errors
/// [`LoadError::Parse`] naming the line and column of what is wrong; a line
/// reader's failure ([`super::line_error`]).
pub(super) fn read_mmcif<R: Read>(
    lines: &mut LineReader<R>,
    label: &str,
) -> Result<Raw, LoadError> {
    let mut reader = CifReader::new(label);
    let mut scratch = String::new();
    let mut tokens: Vec<Token> = Vec::new();
    while let Some((number, bytes)) = lines.next_line().map_err(|e| line_error(label, e))? {
        let line = ascii_line(bytes, &mut scratch);
        if reader.line(number, line, &mut tokens)? {
            break;
        }
    }
    reader.finish(lines.line_number())
}

/// A token's kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// `_category.item`.
    Tag,
    /// `loop_`.
    Loop,
    /// `data_NAME`.
    Data,
    /// `save_`, `global_`, `stop_`: nothing bump reads.
    Reserved,
    /// A value, unquoted.
    Bare,
    /// A value in quotes (the span without them).
    Quoted,
}

/// A token of one line: its kind and its byte span.
#[derive(Debug, Clone, Copy)]
struct Token {
    kind: Kind,
    start: usize,
    end: usize,
}

/// The tokens of one line (not a text-field line), into `out`.
fn tokenize(line: &str, out: &mut Vec<Token>) {
    out.clear();
    let b = line.as_bytes();
    let blank = |c: u8| c == b' ' || c == b'\t';
    let mut i = 0;
    while i < b.len() {
        if blank(b[i]) {
            i += 1;
            continue;
        }
        if b[i] == b'#' {
            break;
        }
        if b[i] == b'\'' || b[i] == b'"' {
            let quote = b[i];
            let start = i + 1;
            let mut j = start;
            while j < b.len() && !(b[j] == quote && b.get(j + 1).is_none_or(|&c| blank(c))) {
                j += 1;
            }
            out.push(Token {
                kind: Kind::Quoted,
                start,
                end: j,
            });
            i = j + 1;
            continue;
        }
        let start = i;
        while i < b.len() && !blank(b[i]) {
            i += 1;
        }
        let word = &b[start..i];
        let starts = |p: &[u8]| word.len() >= p.len() && word[..p.len()].eq_ignore_ascii_case(p);
        let kind = if word[0] == b'_' {
            Kind::Tag
        } else if word.eq_ignore_ascii_case(b"loop_") {
            Kind::Loop
        } else if starts(b"data_") {
            Kind::Data
        } else if starts(b"save_")
            || word.eq_ignore_ascii_case(b"global_")
            || word.eq_ignore_ascii_case(b"stop_")
        {
            Kind::Reserved
        } else {
            Kind::Bare
        };
        out.push(Token {
            kind,
            start,
            end: i,
        });
    }
}

/// The categories kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Category {
    AtomSite,
    StructConn,
}

impl Category {
    /// The category of tag `_category.item`, when it is one kept, with the
    /// item.
    fn of_tag(tag: &str) -> Option<(Self, &str)> {
        let (category, item) = tag.get(1..)?.split_once('.')?;
        if category.eq_ignore_ascii_case("atom_site") {
            Some((Category::AtomSite, item))
        } else if category.eq_ignore_ascii_case("struct_conn") {
            Some((Category::StructConn, item))
        } else {
            None
        }
    }

    fn name(self) -> &'static str {
        match self {
            Category::AtomSite => "_atom_site",
            Category::StructConn => "_struct_conn",
        }
    }
}

/// One value of a row: its text (in the row's buffer), whether it was
/// quoted, and where it was.
#[derive(Debug, Clone, Copy)]
struct Cell {
    start: usize,
    end: usize,
    quoted: bool,
    line: usize,
    column: usize,
}

/// A row being read: the values' text and their cells.
#[derive(Debug, Default)]
struct Row {
    text: String,
    cells: Vec<Cell>,
}

impl Row {
    fn clear(&mut self) {
        self.text.clear();
        self.cells.clear();
    }

    fn push(&mut self, value: &str, quoted: bool, line: usize, column: usize) {
        let start = self.text.len();
        self.text.push_str(value);
        self.cells.push(Cell {
            start,
            end: self.text.len(),
            quoted,
            line,
            column,
        });
    }
}

/// Where the reader is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Between items and loops.
    Top,
    /// After a tag outside a loop: its value comes next (kept when the tag
    /// is one of a kept category's, at that column).
    Value(Option<usize>),
    /// After `loop_`: reading its tags.
    Header,
    /// Reading a loop's values.
    Body,
}

/// The state of a CIF read.
struct CifReader<'a> {
    label: &'a str,
    mode: Mode,
    /// A `data_` line was seen.
    in_block: bool,
    /// The text field being read: its first line, its text (up to
    /// [`MAX_TEXT_FIELD`]) and whether it was cut.
    text_field: Option<(usize, String, bool)>,
    /// The current loop's or item group's category, when kept.
    category: Option<Category>,
    /// The current loop's item names (kept categories only).
    columns: Vec<String>,
    /// The current loop's column count.
    width: usize,
    /// Values of the current loop read so far (for skipped loops, to know
    /// where rows end: not needed, but counted for the loop's own check).
    values: usize,
    /// Line of the current `loop_`.
    loop_line: usize,
    /// The row being read.
    row: Row,
    /// Rows of this loop come one per line (its first row did).
    one_per_line: Option<bool>,
    atoms: AtomSite,
    bonds: StructConn,
    raw: Raw,
}

impl<'a> CifReader<'a> {
    fn new(label: &'a str) -> Self {
        Self {
            label,
            mode: Mode::Top,
            in_block: false,
            text_field: None,
            category: None,
            columns: Vec::new(),
            width: 0,
            values: 0,
            loop_line: 0,
            row: Row::default(),
            one_per_line: None,
            atoms: AtomSite::default(),
            bonds: StructConn::default(),
            raw: Raw::default(),
        }
    }

    fn error(&self, line: usize, column: Option<usize>, reason: impl Into<String>) -> LoadError {
        LoadError::parse_at(self.label, Some(line), column, reason)
    }

    /// Reads line `number`; true when the first data block has ended.
    fn line(
        &mut self,
        number: usize,
        line: &str,
        tokens: &mut Vec<Token>,
    ) -> Result<bool, LoadError> {
        if let Some((_, text, cut)) = &mut self.text_field {
            if let Some(rest) = line.strip_prefix(';') {
                let Some((first, text, cut)) = self.text_field.take() else {
                    return Ok(false);
                };
                self.value(&text, true, first, 1, cut)?;
                return self.tokens(number, rest, 1, tokens);
            }
            if !*cut {
                if text.len() + line.len() < MAX_TEXT_FIELD {
                    text.push('\n');
                    text.push_str(line);
                } else {
                    *cut = true;
                }
            }
            return Ok(false);
        }
        if let Some(rest) = line.strip_prefix(';') {
            let cut = rest.len() > MAX_TEXT_FIELD;
            let text = if cut { String::new() } else { rest.to_string() };
            self.text_field = Some((number, text, cut));
            return Ok(false);
        }
        self.tokens(number, line, 0, tokens)
    }

    /// Handles the tokens of `line` (which starts at byte `offset` of the
    /// file's line `number`); true when the first data block has ended.
    fn tokens(
        &mut self,
        number: usize,
        line: &str,
        offset: usize,
        tokens: &mut Vec<Token>,
    ) -> Result<bool, LoadError> {
        tokenize(line, tokens);
        if tokens.is_empty() {
            return Ok(false);
        }
        // Lines are ASCII here (`ascii_line`): a byte is a column.
        let column =
            |t: &Token| offset + 1 + t.start.saturating_sub(usize::from(t.kind == Kind::Quoted));
        // Rows one per line: a line of values only, at a row's start, is
        // one row, and its values must fill it.
        if self.mode == Mode::Body
            && self.category.is_some()
            && self.row.cells.is_empty()
            && self.one_per_line == Some(true)
            && tokens
                .iter()
                .all(|t| matches!(t.kind, Kind::Bare | Kind::Quoted))
            && tokens.len() != self.width
        {
            let (category, n) = (self.category_name(), self.width);
            return Err(self.error(
                number,
                Some(column(&tokens[0])),
                format!(
                    "this {category} row has {} values; the loop has {n} columns",
                    tokens.len()
                ),
            ));
        }
        // The common case, a whole row on its line (its values were
        // counted above): read in place.
        if self.mode == Mode::Body
            && self.category.is_some()
            && self.row.cells.is_empty()
            && self.one_per_line == Some(true)
            && tokens
                .iter()
                .all(|t| matches!(t.kind, Kind::Bare | Kind::Quoted))
        {
            self.row.cells.clear();
            self.row.cells.extend(tokens.iter().map(|t| Cell {
                start: t.start,
                end: t.end,
                quoted: t.kind == Kind::Quoted,
                line: number,
                column: column(t),
            }));
            self.values += tokens.len();
            let result = self.emit(line);
            self.row.cells.clear();
            return result.map(|()| false);
        }
        let first_row = matches!(self.mode, Mode::Header | Mode::Body)
            && self.one_per_line.is_none()
            && self.row.cells.is_empty()
            && matches!(tokens[0].kind, Kind::Bare | Kind::Quoted);
        for (k, t) in tokens.iter().enumerate() {
            let text = &line[t.start..t.end];
            let col = column(t);
            match t.kind {
                Kind::Bare | Kind::Quoted => {
                    self.value(text, t.kind == Kind::Quoted, number, col, false)?;
                    if first_row
                        && self.one_per_line.is_none()
                        && self.row.cells.is_empty()
                        && self.values > 0
                    {
                        // The loop's first row ended on this token.
                        self.one_per_line = Some(k + 1 == tokens.len());
                    }
                }
                Kind::Tag => {
                    self.missing_value(number, col)?;
                    if self.mode == Mode::Body {
                        self.end_of_loop()?;
                    }
                    self.tag(text, number)?;
                }
                Kind::Loop => {
                    self.missing_value(number, col)?;
                    self.end_of_loop()?;
                    self.end_of_items()?;
                    self.mode = Mode::Header;
                    self.category = None;
                    self.columns.clear();
                    self.width = 0;
                    self.values = 0;
                    self.loop_line = number;
                    self.one_per_line = None;
                }
                Kind::Data => {
                    self.missing_value(number, col)?;
                    self.end_of_loop()?;
                    self.end_of_items()?;
                    if self.in_block {
                        return Ok(true);
                    }
                    self.in_block = true;
                    self.mode = Mode::Top;
                }
                Kind::Reserved => {
                    self.missing_value(number, col)?;
                    self.end_of_loop()?;
                    self.end_of_items()?;
                }
            }
        }
        if first_row && self.one_per_line.is_none() && !self.row.cells.is_empty() {
            self.one_per_line = Some(false);
        }
        Ok(false)
    }

    fn category_name(&self) -> &'static str {
        self.category.map_or("", Category::name)
    }

    /// A tag outside a loop's body.
    fn tag(&mut self, tag: &str, line: usize) -> Result<(), LoadError> {
        let kept = Category::of_tag(tag);
        if self.mode == Mode::Header {
            if self.width == 0 {
                self.category = kept.map(|(c, _)| c);
            }
            self.width += 1;
            if self.category.is_some() {
                let item = match kept {
                    Some((c, item)) if Some(c) == self.category => item,
                    _ => "",
                };
                self.columns.push(item.to_ascii_lowercase());
            }
            return Ok(());
        }
        // An item outside a loop: a kept category's items make one row.
        match kept {
            Some((c, item)) => {
                if self.category != Some(c) {
                    self.end_of_items()?;
                    self.category = Some(c);
                    self.loop_line = line;
                }
                self.columns.push(item.to_ascii_lowercase());
                self.mode = Mode::Value(Some(self.columns.len() - 1));
            }
            None => {
                self.end_of_items()?;
                self.mode = Mode::Value(None);
            }
        }
        Ok(())
    }

    /// A value (of a loop or an item), at `line` and `column`; `cut` when
    /// it is a text field too long to keep.
    fn value(
        &mut self,
        text: &str,
        quoted: bool,
        line: usize,
        column: usize,
        cut: bool,
    ) -> Result<(), LoadError> {
        match self.mode {
            Mode::Top => Ok(()),
            Mode::Value(None) => {
                self.mode = Mode::Top;
                Ok(())
            }
            Mode::Value(Some(_)) => {
                if cut {
                    return Err(self.error(
                        line,
                        Some(column),
                        "a text field too long for an atom or bond value",
                    ));
                }
                self.row.push(text, quoted, line, column);
                self.mode = Mode::Top;
                Ok(())
            }
            Mode::Header => {
                self.mode = Mode::Body;
                if self.category.is_some() {
                    self.begin_table()?;
                }
                self.value(text, quoted, line, column, cut)
            }
            Mode::Body => {
                self.values += 1;
                if self.category.is_none() {
                    return Ok(());
                }
                if cut {
                    return Err(self.error(
                        line,
                        Some(column),
                        "a text field too long for an atom or bond value",
                    ));
                }
                self.row.push(text, quoted, line, column);
                if self.row.cells.len() == self.width {
                    self.emit_row()?;
                    self.row.clear();
                }
                Ok(())
            }
        }
    }

    /// The column layout of a kept loop (or item group), before its rows.
    fn begin_table(&mut self) -> Result<(), LoadError> {
        let line = self.loop_line;
        match self.category {
            Some(Category::AtomSite) => {
                self.atoms.columns =
                    AtomColumns::find(&self.columns).map_err(|r| self.error(line, None, r))?;
            }
            Some(Category::StructConn) => self.bonds.columns = ConnColumns::find(&self.columns),
            None => {}
        }
        Ok(())
    }

    /// Hands a full row to its category.
    fn emit_row(&mut self) -> Result<(), LoadError> {
        let text = std::mem::take(&mut self.row.text);
        let result = self.emit(&text);
        self.row.text = text;
        result
    }

    /// Hands the row whose cells are `self.row.cells`, spans of `text`, to
    /// its category.
    fn emit(&mut self, text: &str) -> Result<(), LoadError> {
        let row = RowView {
            text,
            cells: &self.row.cells,
        };
        match self.category {
            Some(Category::AtomSite) => {
                self.atoms
                    .row(&row, &mut self.raw)
                    .map_err(|(cell, reason)| {
                        let c = row.cells.get(cell).copied();
                        LoadError::parse_at(
                            self.label,
                            c.map(|c| c.line),
                            c.map(|c| c.column),
                            reason,
                        )
                    })
            }
            Some(Category::StructConn) => {
                if let Err((cell, reason)) = self.bonds.row(&row, &mut self.raw) {
                    self.bonds.warnings += 1;
                    if self.bonds.warnings <= MAX_BOND_WARNINGS {
                        let c = row.cells.get(cell).copied();
                        self.raw.warnings.push(format!(
                            "{}:{}:{}: {reason}; the bond is skipped",
                            self.label,
                            c.map_or(0, |c| c.line),
                            c.map_or(0, |c| c.column)
                        ));
                    }
                }
                Ok(())
            }
            None => Ok(()),
        }
    }

    /// Ends a loop (a row left unfilled in a kept one is an error), or a
    /// loop of tags without values.
    fn end_of_loop(&mut self) -> Result<(), LoadError> {
        match self.mode {
            Mode::Header => {}
            Mode::Body => {
                if let (Some(c), Some(first)) = (self.category, self.row.cells.first().copied()) {
                    return Err(self.error(
                        first.line,
                        Some(first.column),
                        format!(
                            "the {} loop ends inside a row: {} of its {} values are there",
                            c.name(),
                            self.row.cells.len(),
                            self.width
                        ),
                    ));
                }
            }
            Mode::Top | Mode::Value(_) => return Ok(()),
        }
        self.mode = Mode::Top;
        self.category = None;
        self.columns.clear();
        self.row.clear();
        Ok(())
    }

    /// A reserved word or tag where an item's value should be.
    fn missing_value(&mut self, line: usize, column: usize) -> Result<(), LoadError> {
        match self.mode {
            Mode::Value(Some(k)) => {
                let item = self.columns.get(k).cloned().unwrap_or_default();
                Err(self.error(
                    line,
                    Some(column),
                    format!(
                        "the item {} has no value before this",
                        excerpt(&format!("{}.{item}", self.category_name()))
                    ),
                ))
            }
            Mode::Value(None) => {
                self.mode = Mode::Top;
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// Ends a group of items outside a loop: a kept category's make a row.
    fn end_of_items(&mut self) -> Result<(), LoadError> {
        if matches!(self.mode, Mode::Header | Mode::Body) || self.category.is_none() {
            return Ok(());
        }
        if self.row.cells.len() == self.columns.len() && !self.columns.is_empty() {
            self.width = self.columns.len();
            self.begin_table()?;
            self.emit_row()?;
        }
        self.row.clear();
        self.columns.clear();
        self.category = None;
        Ok(())
    }

    /// The end of the text: what is left open is closed or refused.
    fn finish(mut self, last_line: usize) -> Result<Raw, LoadError> {
        if let Some((first, _, _)) = &self.text_field {
            return Err(self.error(
                *first,
                Some(1),
                "a text field opened here (a line starting with ;) is never closed",
            ));
        }
        if let Mode::Value(Some(_)) = self.mode {
            return Err(self.error(
                last_line,
                None,
                "the file ends before the value of its last item",
            ));
        }
        self.end_of_loop()?;
        self.end_of_items()?;
        if self.bonds.warnings > MAX_BOND_WARNINGS {
            self.raw.warnings.push(format!(
                "{}: ... and {} more struct_conn bonds skipped",
                self.label,
                self.bonds.warnings - MAX_BOND_WARNINGS
            ));
        }
        Ok(self.raw)
    }
}

/// A full row: its values' text and where each was.
struct RowView<'r> {
    text: &'r str,
    cells: &'r [Cell],
}

impl<'r> RowView<'r> {
    /// The value at `column` as written (empty when there is none).
    fn raw(&self, column: usize) -> &'r str {
        self.cells
            .get(column)
            .and_then(|c| self.text.get(c.start..c.end))
            .unwrap_or("")
    }

    /// The value at `column`, unless it is absent, `?` or `.` unquoted.
    fn get(&self, column: Option<usize>) -> Option<&'r str> {
        let c = column?;
        let cell = self.cells.get(c)?;
        let v = self.text.get(cell.start..cell.end)?;
        (cell.quoted || (v != "?" && v != ".")).then_some(v)
    }
}

/// A problem with a row: the index of the value it is about and the message.
type RowError = (usize, String);

/// Where the `_atom_site` items the atoms need are.
#[derive(Debug, Default, Clone, Copy)]
struct AtomColumns {
    group: Option<usize>,
    id: Option<usize>,
    symbol: Option<usize>,
    name: usize,
    alt: Option<usize>,
    residue: usize,
    chain: Option<usize>,
    label_chain: Option<usize>,
    seq: Option<usize>,
    label_seq: Option<usize>,
    insertion: Option<usize>,
    xyz: [usize; 3],
    occupancy: Option<usize>,
    model: Option<usize>,
}

impl AtomColumns {
    /// The layout of a loop with `columns` (lower case); the error names a
    /// column the atoms need that it lacks.
    fn find(columns: &[String]) -> Result<Self, String> {
        let at = |name: &str| columns.iter().position(|c| c == name);
        let either = |a: &str, b: &str| at(a).or_else(|| at(b));
        let need = |c: Option<usize>, name: &str| {
            c.ok_or_else(|| format!("the _atom_site loop has no {name} column"))
        };
        Ok(Self {
            group: at("group_pdb"),
            id: at("id"),
            symbol: at("type_symbol"),
            name: need(either("label_atom_id", "auth_atom_id"), "label_atom_id")?,
            alt: at("label_alt_id"),
            residue: need(either("label_comp_id", "auth_comp_id"), "label_comp_id")?,
            chain: at("auth_asym_id"),
            label_chain: at("label_asym_id"),
            seq: at("auth_seq_id"),
            label_seq: at("label_seq_id"),
            insertion: at("pdbx_pdb_ins_code"),
            xyz: [
                need(at("cartn_x"), "Cartn_x")?,
                need(at("cartn_y"), "Cartn_y")?,
                need(at("cartn_z"), "Cartn_z")?,
            ],
            occupancy: at("occupancy"),
            model: at("pdbx_pdb_model_num"),
        })
    }
}

/// The `_atom_site` reader's state.
#[derive(Debug, Default)]
struct AtomSite {
    columns: AtomColumns,
    /// The first row's model number (as written).
    model: Option<String>,
    /// Rows read.
    rows: usize,
    /// Residues seen without a number: they are numbered in order.
    unnumbered: i64,
    /// The previous row's (chain, residue) when it had no number.
    previous: Option<(ChainId, ResidueName)>,
}

/// A label read from a value, refused when longer than the label holds.
fn label<const N: usize>(value: &str, what: &str, cell: usize) -> Result<Label<N>, RowError> {
    if let Some(c) = value.chars().find(char::is_ascii_control) {
        return Err((
            cell,
            format!(
                "control character U+{:04X} in {what} {} (names must be printable)",
                u32::from(c),
                excerpt(value)
            ),
        ));
    }
    Label::new(value).ok_or_else(|| {
        (
            cell,
            format!(
                "{what} {} is longer than the {N} characters bump keeps",
                excerpt(value)
            ),
        )
    })
}

impl AtomSite {
    /// Reads one row into `raw`.
    fn row(&mut self, row: &RowView<'_>, raw: &mut Raw) -> Result<(), RowError> {
        let c = self.columns;
        self.rows += 1;
        if let Some(m) = c.model {
            let here = row.raw(m);
            match &self.model {
                None => self.model = Some(here.to_string()),
                Some(first) if first != here => return Ok(()),
                Some(_) => {}
            }
        }
        let hetero = match row.get(c.group) {
            None => false,
            Some(g) if g.eq_ignore_ascii_case("ATOM") => false,
            Some(g) if g.eq_ignore_ascii_case("HETATM") => true,
            Some(g) => {
                return Err((
                    c.group.unwrap_or(0),
                    format!("group_PDB is {}, not ATOM or HETATM", excerpt(g)),
                ));
            }
        };
        let serial = match (c.id, row.get(c.id)) {
            (Some(i), Some(v)) => v.parse::<i64>().map_err(|_| {
                (
                    i,
                    format!("the atom id {} is not a whole number", excerpt(v)),
                )
            })?,
            (Some(i), None) => return Err((i, "the atom id is missing".to_string())),
            (None, _) => i64::try_from(self.rows).unwrap_or(i64::MAX),
        };
        let name: AtomName = match row.get(Some(c.name)) {
            Some(v) => label(v, "the atom name", c.name)?,
            None => return Err((c.name, format!("atom {serial} has no name"))),
        };
        let residue: ResidueName = match row.get(Some(c.residue)) {
            Some(v) => label(v, "the residue name", c.residue)?,
            None => return Err((c.residue, format!("atom {serial} has no residue name"))),
        };
        let element: ElementSymbol = match c.symbol {
            None => Label::truncated(&guess_from_name(&name)),
            Some(s) => match row.get(Some(s)) {
                Some(v) => {
                    // Refuses control characters and overlong symbols.
                    label::<{ ElementSymbol::CAPACITY }>(v, "the element symbol", s)?;
                    element_label(v).unwrap_or_default()
                }
                None => {
                    return Err((
                        s,
                        format!("atom {serial} ({name}) has no element (type_symbol is ? or .)"),
                    ));
                }
            },
        };
        let chain_column = if row.get(c.chain).is_some() {
            c.chain
        } else {
            c.label_chain
        };
        let chain: ChainId = match row.get(chain_column) {
            Some(v) => label(v, "the chain", chain_column.unwrap_or(0))?,
            None => Label::EMPTY,
        };
        let seq_column = if row.get(c.seq).is_some() {
            c.seq
        } else {
            c.label_seq
        };
        let seq = match row.get(seq_column) {
            Some(v) => v.parse::<i64>().map_err(|_| {
                (
                    seq_column.unwrap_or(0),
                    format!("the residue number {} is not a whole number", excerpt(v)),
                )
            })?,
            None => {
                if self.previous != Some((chain, residue)) {
                    self.unnumbered += 1;
                    self.previous = Some((chain, residue));
                }
                self.unnumbered
            }
        };
        if seq_column.is_some() && row.get(seq_column).is_some() {
            self.previous = None;
        }
        let insertion: InsertionCode = match row.get(c.insertion) {
            Some(v) => label(v, "the insertion code", c.insertion.unwrap_or(0))?,
            None => Label::EMPTY,
        };
        let alt = match row.get(c.alt) {
            None => 0,
            Some(v) if v.len() == 1 => v.as_bytes()[0],
            Some(v) => {
                return Err((
                    c.alt.unwrap_or(0),
                    format!("the alternate location {} is not one character", excerpt(v)),
                ));
            }
        };
        let mut xyz = [0.0; 3];
        for ((slot, &col), axis) in xyz
            .iter_mut()
            .zip(&c.xyz)
            .zip(["Cartn_x", "Cartn_y", "Cartn_z"])
        {
            let v = row.raw(col);
            *slot = v.parse::<f64>().map_err(|_| {
                (
                    col,
                    format!("{axis} of atom {serial} is not a number: {}", excerpt(v)),
                )
            })?;
        }
        let position =
            check_position(DVec3::from_array(xyz), serial, &name).map_err(|r| (c.xyz[0], r))?;
        let occupancy = match row.get(c.occupancy) {
            None => 1.0,
            Some(v) => v.parse::<f64>().map_err(|_| {
                (
                    c.occupancy.unwrap_or(0),
                    format!(
                        "the occupancy of atom {serial} is not a number: {}",
                        excerpt(v)
                    ),
                )
            })? as f32,
        };
        raw.push(
            AtomInfo {
                serial,
                name,
                residue,
                seq,
                insertion,
                chain,
                element,
                radius: 0.0,
                polar: false,
                hetero,
            },
            position,
            occupancy,
            alt,
        );
        Ok(())
    }
}

/// Where the `_struct_conn` items the bonds need are, for each partner.
#[derive(Debug, Default, Clone)]
struct ConnColumns {
    kind: Option<usize>,
    order: Option<usize>,
    partners: [Partner; 2],
}

/// The columns naming one partner of a `_struct_conn` row.
#[derive(Debug, Default, Clone, Copy)]
struct Partner {
    chain: Option<usize>,
    label_chain: Option<usize>,
    seq: Option<usize>,
    label_seq: Option<usize>,
    insertion: Option<usize>,
    name: Option<usize>,
    residue: Option<usize>,
    alt: Option<usize>,
    symmetry: Option<usize>,
}

impl ConnColumns {
    fn find(columns: &[String]) -> Self {
        let at = |name: &str| columns.iter().position(|c| c == name);
        let partner = |p: &str| Partner {
            chain: at(&format!("{p}_auth_asym_id")),
            label_chain: at(&format!("{p}_label_asym_id")),
            seq: at(&format!("{p}_auth_seq_id")),
            label_seq: at(&format!("{p}_label_seq_id")),
            insertion: at(&format!("pdbx_{p}_pdb_ins_code")),
            name: at(&format!("{p}_label_atom_id"))
                .or_else(|| at(&format!("pdbx_{p}_auth_atom_id"))),
            residue: at(&format!("{p}_label_comp_id")).or_else(|| at(&format!("{p}_auth_comp_id"))),
            alt: at(&format!("pdbx_{p}_label_alt_id")),
            symmetry: at(&format!("{p}_symmetry")),
        };
        Self {
            kind: at("conn_type_id"),
            order: at("pdbx_value_order"),
            partners: [partner("ptnr1"), partner("ptnr2")],
        }
    }
}

/// The `_struct_conn` reader's state.
#[derive(Debug, Default)]
struct StructConn {
    columns: ConnColumns,
    /// Rows skipped for a problem.
    warnings: usize,
}

impl StructConn {
    /// Reads one row: a covalent bond (`covale*`, `disulf`) between atoms
    /// of this asymmetric unit becomes a pending bond; other connections
    /// (metal coordination, hydrogen bonds, mismatches) are not bonds.
    fn row(&mut self, row: &RowView<'_>, raw: &mut Raw) -> Result<(), RowError> {
        let c = self.columns.clone();
        let Some(kind) = row.get(c.kind) else {
            return Ok(());
        };
        let kind = kind.to_ascii_lowercase();
        if !(kind.starts_with("covale") || kind == "disulf") {
            return Ok(());
        }
        let order = match row.get(c.order).map(str::to_ascii_lowercase).as_deref() {
            Some("sing") => BondOrder::Single,
            Some("doub") => BondOrder::Double,
            Some("trip") => BondOrder::Triple,
            Some("arom") => BondOrder::Aromatic,
            _ => BondOrder::Unspecified,
        };
        let mut ends = [None; 2];
        for (end, p) in ends.iter_mut().zip(c.partners) {
            if row.get(p.symmetry).is_some_and(|s| s != "1_555") {
                // A bond to a symmetry copy: not an atom of the file.
                return Ok(());
            }
            *end = Some(partner(row, &p)?);
        }
        if let [Some(a), Some(b)] = ends {
            raw.bonds.named.push(NamedBond { a, b, order });
        }
        Ok(())
    }
}

/// One partner of a `_struct_conn` row, named as atoms keep their names.
fn partner(row: &RowView<'_>, p: &Partner) -> Result<AtomRef, RowError> {
    let chain_column = if row.get(p.chain).is_some() {
        p.chain
    } else {
        p.label_chain
    };
    let seq_column = if row.get(p.seq).is_some() {
        p.seq
    } else {
        p.label_seq
    };
    let name_column = p.name.unwrap_or(0);
    let Some(name) = row.get(p.name) else {
        return Err((
            name_column,
            "a bond partner without an atom name".to_string(),
        ));
    };
    let seq = match row.get(seq_column) {
        Some(v) => v.parse().map_err(|_| {
            (
                seq_column.unwrap_or(0),
                format!("the residue number {} is not a whole number", excerpt(v)),
            )
        })?,
        None => {
            return Err((
                name_column,
                "a bond partner without a residue number".to_string(),
            ));
        }
    };
    Ok(AtomRef {
        chain: match row.get(chain_column) {
            Some(v) => label(v, "the chain", chain_column.unwrap_or(0))?,
            None => Label::EMPTY,
        },
        seq,
        insertion: match row.get(p.insertion) {
            Some(v) => label(v, "the insertion code", p.insertion.unwrap_or(0))?,
            None => Label::EMPTY,
        },
        name: label(name, "the atom name", name_column)?,
        residue: match row.get(p.residue) {
            Some(v) => label(v, "the residue name", p.residue.unwrap_or(0))?,
            None => Label::EMPTY,
        },
        alt: match row.get(p.alt) {
            Some(v) if v.len() == 1 => v.as_bytes()[0],
            _ => 0,
        },
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    fn words(line: &str) -> Vec<(Kind, &str)> {
        let mut out = Vec::new();
        tokenize(line, &mut out);
        out.iter()
            .map(|t| (t.kind, &line[t.start..t.end]))
            .collect()
    }

    #[test]
    fn tokens_keep_quoted_values_whole() {
        assert_eq!(
            words("ATOM 1 O \"O5'\" . 'A B' 1.0 # note"),
            [
                (Kind::Bare, "ATOM"),
                (Kind::Bare, "1"),
                (Kind::Bare, "O"),
                (Kind::Quoted, "O5'"),
                (Kind::Bare, "."),
                (Kind::Quoted, "A B"),
                (Kind::Bare, "1.0"),
            ]
        );
        assert!(words("  ").is_empty());
        assert_eq!(
            words("LOOP_ _Atom_Site.id data_x save_ stop_ 'it''s'"),
            [
                (Kind::Loop, "LOOP_"),
                (Kind::Tag, "_Atom_Site.id"),
                (Kind::Data, "data_x"),
                (Kind::Reserved, "save_"),
                (Kind::Reserved, "stop_"),
                (Kind::Quoted, "it''s"),
            ]
        );
        // An unclosed quote runs to the line's end.
        assert_eq!(words("'abc"), [(Kind::Quoted, "abc")]);
    }

    fn read(text: &str) -> Result<Raw, LoadError> {
        let mut lines = LineReader::new(text.as_bytes(), 1 << 20);
        read_mmcif(&mut lines, "t.cif")
    }

    #[test]
    fn other_categories_text_fields_and_later_blocks_are_passed_over() {
        let text = "data_X\n_cell.a 1\n_struct.title\n;\nloop_\n_atom_site.id\n;\nloop_\n_atom_site.id\n\
                    _atom_site.label_atom_id\n_atom_site.label_comp_id\n_atom_site.Cartn_x\n\
                    _atom_site.Cartn_y\n_atom_site.Cartn_z\n1 N ALA 1 2 3\n2 CA ALA 4 5 6\n#\n\
                    data_Y\nloop_\n_atom_site.id\n";
        let raw = read(text).unwrap();
        assert_eq!(raw.atoms.len(), 2);
        assert_eq!(raw.atoms[1].name, "CA");
        assert_eq!(raw.atoms[1].element, "C");
        assert_eq!(raw.positions[1], DVec3::new(4.0, 5.0, 6.0));
    }

    #[test]
    fn a_single_atom_may_be_written_as_items() {
        let text = "data_X\n_atom_site.id 7\n_atom_site.type_symbol Fe\n_atom_site.label_atom_id FE\n\
                    _atom_site.label_comp_id HEM\n_atom_site.Cartn_x 1\n_atom_site.Cartn_y 2\n\
                    _atom_site.Cartn_z 3\n_other.x y\n";
        let raw = read(text).unwrap();
        assert_eq!(raw.atoms.len(), 1);
        assert_eq!(
            (raw.atoms[0].serial, raw.atoms[0].element.as_str()),
            (7, "Fe")
        );
    }

    #[test]
    fn rows_may_run_over_lines_where_the_first_did() {
        let text = "data_X\nloop_\n_atom_site.id\n_atom_site.label_atom_id\n_atom_site.label_comp_id\n\
                    _atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n1 N ALA\n1 2 3\n2 CA\nALA 4 5 6\n";
        assert_eq!(read(text).unwrap().atoms.len(), 2);
        let cut = text.replace("ALA 4 5 6\n", "ALA 4 5\n");
        let e = read(&cut).unwrap_err().to_string();
        assert!(
            e.contains("t.cif:11:1: the _atom_site loop ends inside a row: 5 of its 6"),
            "{e}"
        );
    }

    #[test]
    fn an_unclosed_text_field_is_named() {
        let e = read("data_X\n_a.b\n;\ntext\n").unwrap_err().to_string();
        assert!(e.starts_with("t.cif:3:1: a text field"), "{e}");
    }

    #[test]
    fn covalent_struct_conn_rows_become_bonds() {
        let text = "data_X\nloop_\n_struct_conn.id\n_struct_conn.conn_type_id\n\
                    _struct_conn.ptnr1_auth_asym_id\n_struct_conn.ptnr1_auth_seq_id\n\
                    _struct_conn.ptnr1_label_atom_id\n_struct_conn.ptnr1_label_comp_id\n\
                    _struct_conn.ptnr1_symmetry\n_struct_conn.ptnr2_auth_asym_id\n\
                    _struct_conn.ptnr2_auth_seq_id\n_struct_conn.ptnr2_label_atom_id\n\
                    _struct_conn.ptnr2_label_comp_id\n_struct_conn.ptnr2_symmetry\n\
                    _struct_conn.pdbx_value_order\n\
                    disulf1 disulf A 3 SG CYS 1_555 A 40 SG CYS 1_555 ?\n\
                    covale1 covale A 5 C1 NAG 1_555 A 6 O4 NAG 1_555 sing\n\
                    metalc1 metalc A 7 ZN ZN 1_555 A 3 SG CYS 1_555 ?\n\
                    disulf2 disulf A 3 SG CYS 1_555 A 40 SG CYS 2_555 ?\n";
        let raw = read(text).unwrap();
        let named = &raw.bonds.named;
        assert_eq!(named.len(), 2);
        assert_eq!((named[0].a.seq, named[0].b.seq), (3, 40));
        assert_eq!(named[0].order, BondOrder::Unspecified);
        assert_eq!(named[1].order, BondOrder::Single);
        assert_eq!(named[1].b.name, "O4");
    }
}
