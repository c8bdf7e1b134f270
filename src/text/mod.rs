//! Text from files, as every reader takes it: lines ended by LF, CRLF or a
//! lone CR ([`lines`]), files read with a bound on their (decompressed) size
//! ([`source`]), and the short forms in which messages quote what they read:
//! an excerpt of at most [`EXCERPT_CHARS`] characters ([`excerpt`]) and
//! numbers that print in a few characters whatever their size
//! ([`short_number`]).
//!
//! A message about bad input names the file, the line and, where it helps,
//! the column, and quotes only an excerpt: a file of one 100 MB line must
//! not come back as 100 MB of error message.

pub mod lines;
pub mod source;

pub use lines::{LineReader, split_lines};
pub use source::{
    DEFAULT_DECOMPRESSED_LIMIT, SourceError, TextSource, format_bytes, parse_byte_size,
    read_limited,
};

/// Most characters of input a message quotes.
pub const EXCERPT_CHARS: usize = 80;

/// `text` quoted as Rust debug-formats a string (control characters
/// escaped), cut after [`EXCERPT_CHARS`] characters on a character boundary;
/// a cut excerpt ends in `…` after the closing quote and says how long the
/// whole was: `"ATOM      1 …"… (5000000 bytes)`.
pub fn excerpt(text: &str) -> String {
    match text.char_indices().nth(EXCERPT_CHARS) {
        None => format!("{text:?}"),
        Some((cut, _)) => format!("{:?}… ({} bytes)", &text[..cut], text.len()),
    }
}

/// `text` in backquotes when it is short and printable (`` `CA` ``), else
/// its [`excerpt`].
pub fn quoted(text: &str) -> String {
    if text.len() <= EXCERPT_CHARS && !text.chars().any(char::is_control) {
        format!("`{text}`")
    } else {
        excerpt(text)
    }
}

/// [`excerpt`] of bytes that may not be UTF-8 (invalid sequences shown as
/// U+FFFD). Only the first few hundred bytes are looked at, so a huge
/// input costs nothing.
pub fn excerpt_bytes(bytes: &[u8]) -> String {
    // Four bytes per character at most, plus one partly cut.
    let head = &bytes[..bytes.len().min(4 * EXCERPT_CHARS + 4)];
    let text = String::from_utf8_lossy(head);
    match text.char_indices().nth(EXCERPT_CHARS) {
        None if head.len() == bytes.len() => format!("{text:?}"),
        None => format!("{text:?}… ({} bytes)", bytes.len()),
        Some((cut, _)) => format!("{:?}… ({} bytes)", &text[..cut], bytes.len()),
    }
}

/// A number as a message shows it: Rust's shortest round-trip form, or its
/// exponent form when that is shorter and the plain one runs past 8
/// characters (`0.03`, `-0.001`, `123456789`, `3e9`, `1e308` rather than
/// 309 digits).
pub fn short_number(v: f64) -> String {
    let plain = format!("{v}");
    let exponent = format!("{v:e}");
    if plain.len() > 8 && exponent.len() < plain.len() {
        exponent
    } else {
        plain
    }
}

/// The 1-based column (in characters) of byte offset `at` in `line`, for
/// messages; an offset inside a character counts as that character.
pub fn column_of(line: &str, at: usize) -> usize {
    let at = at.min(line.len());
    line.char_indices().take_while(|(i, _)| *i < at).count() + 1
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn excerpts_are_short_and_cut_on_a_character_boundary() {
        assert_eq!(excerpt("abc"), "\"abc\"");
        assert_eq!(excerpt("a\rb"), "\"a\\rb\"");
        let long = "é".repeat(1000);
        let e = excerpt(&long);
        assert!(
            e.starts_with(&format!("\"{}\"…", "é".repeat(EXCERPT_CHARS))),
            "{e}"
        );
        assert!(e.ends_with("(2000 bytes)"), "{e}");
        let exact = "x".repeat(EXCERPT_CHARS);
        assert_eq!(excerpt(&exact), format!("{exact:?}"));
    }

    #[test]
    fn short_printable_text_is_backquoted() {
        assert_eq!(quoted("CA"), "`CA`");
        assert_eq!(quoted("a\tb"), "\"a\\tb\"");
        assert!(quoted(&"x".repeat(1000)).ends_with("(1000 bytes)"));
    }

    #[test]
    fn byte_excerpts_read_what_they_can() {
        assert_eq!(excerpt_bytes(b"ab\xffc"), "\"ab\u{fffd}c\"");
        let big = vec![b'z'; 10_000_000];
        let e = excerpt_bytes(&big);
        assert!(e.len() < 120 && e.ends_with("(10000000 bytes)"), "{e}");
        let cut_short = vec![0xff; 1000];
        assert!(excerpt_bytes(&cut_short).ends_with("(1000 bytes)"));
    }

    #[test]
    fn numbers_print_short() {
        assert_eq!(short_number(0.03), "0.03");
        assert_eq!(short_number(-2.5), "-2.5");
        assert_eq!(short_number(1e308), "1e308");
        assert_eq!(short_number(-1e19), "-1e19");
        assert_eq!(short_number(123456789.0), "123456789");
        assert_eq!(short_number(f64::INFINITY), "inf");
        assert_eq!(short_number(f64::NAN), "NaN");
        assert_eq!(short_number(1e-300), "1e-300");
        assert_eq!(short_number(3e9), "3e9");
        assert_eq!(short_number(1e6), "1000000");
        assert_eq!(short_number(-0.001), "-0.001");
        assert_eq!(short_number(1500.0), "1500");
    }

    #[test]
    fn columns_count_characters() {
        assert_eq!(column_of("abc", 0), 1);
        assert_eq!(column_of("éa", 2), 2);
        assert_eq!(column_of("ab", 10), 3);
    }
}
