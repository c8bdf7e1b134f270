//! The CIF tokenizer: one line (not a text-field line) into tokens, each
//! with its kind (tag, `loop_`, `data_`, other reserved word, bare or
//! quoted value) and its byte span. Quoted values run to the same quote
//! followed by a blank or the line's end; `#` outside quotes ends the line.

/// A token's kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
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
pub(super) struct Token {
    pub(super) kind: Kind,
    pub(super) start: usize,
    pub(super) end: usize,
}

/// The tokens of one line (not a text-field line), into `out`.
pub(super) fn tokenize(line: &str, out: &mut Vec<Token>) {
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

#[cfg(test)]
mod tests {
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
}
