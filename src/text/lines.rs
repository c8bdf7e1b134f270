//! Lines ended by LF (Unix), CRLF (Windows) or a lone CR (classic Mac OS,
//! and what some tools still write), read alike: from bytes in memory
//! ([`split_lines`]) or streamed from a reader with a bound on the length of
//! one line ([`LineReader`]), so that a file with no line break at all
//! costs at most that bound.
//!
//! As with [`str::lines`], the last line needs no terminator and a file
//! ending in one has no empty line after it.

use std::io::Read;

/// The lines of `bytes`, without their terminators (LF, CRLF or CR).
pub fn split_lines(bytes: &[u8]) -> SplitLines<'_> {
    SplitLines { rest: bytes }
}

/// The lines of `text`, without their terminators (LF, CRLF or CR).
pub fn split_str(text: &str) -> impl Iterator<Item = &str> {
    // Cut only at ASCII bytes, so every piece is UTF-8 too.
    split_lines(text.as_bytes()).map(|l| std::str::from_utf8(l).unwrap_or_default())
}

/// Iterator of [`split_lines`].
#[derive(Debug, Clone)]
pub struct SplitLines<'a> {
    rest: &'a [u8],
}

impl<'a> Iterator for SplitLines<'a> {
    type Item = &'a [u8];

    fn next(&mut self) -> Option<&'a [u8]> {
        if self.rest.is_empty() {
            return None;
        }
        let rest = self.rest;
        match memchr::memchr2(b'\n', b'\r', rest) {
            None => {
                self.rest = &[];
                Some(rest)
            }
            Some(i) => {
                let next = if rest[i] == b'\r' && rest.get(i + 1) == Some(&b'\n') {
                    i + 2
                } else {
                    i + 1
                };
                self.rest = &rest[next..];
                Some(&rest[..i])
            }
        }
    }
}

/// Why [`LineReader::next_line`] stopped.
#[derive(Debug)]
pub enum LineError {
    /// The reader failed (for a decompressing source, also a size limit).
    Io(std::io::Error),
    /// A line ran past the limit before its end.
    TooLong {
        /// Its 1-based number.
        line: usize,
        /// The limit, bytes.
        limit: usize,
    },
}

/// How much a [`LineReader`] asks its reader for at a time.
const READ_SIZE: usize = 256 * 1024;

/// Lines streamed from a reader, each at most `max_line` bytes long.
#[derive(Debug)]
pub struct LineReader<R> {
    inner: R,
    buf: Vec<u8>,
    /// Start of the unread bytes in `buf`.
    start: usize,
    /// End of the valid bytes in `buf`.
    end: usize,
    /// Bytes from `start` already searched for a line end (so a long line
    /// read in many pieces is searched once).
    searched: usize,
    /// Lines returned so far.
    number: usize,
    /// The last line ended in a CR that was the last byte read: an LF
    /// opening the next read belongs to it.
    skip_lf: bool,
    eof: bool,
    max_line: usize,
}

impl<R: Read> LineReader<R> {
    /// Lines of `inner`, each at most `max_line` bytes.
    pub fn new(inner: R, max_line: usize) -> Self {
        Self {
            inner,
            buf: Vec::new(),
            start: 0,
            end: 0,
            searched: 0,
            number: 0,
            skip_lf: false,
            eof: false,
            max_line,
        }
    }

    /// The 1-based number of the line last returned (0 before the first).
    pub fn line_number(&self) -> usize {
        self.number
    }

    /// The next line without its terminator, with its 1-based number;
    /// `None` at the end.
    ///
    /// # Errors
    /// [`LineError::Io`] when the reader fails, [`LineError::TooLong`] for
    /// a line longer than the limit.
    pub fn next_line(&mut self) -> Result<Option<(usize, &[u8])>, LineError> {
        let range = loop {
            if self.skip_lf && self.start < self.end {
                if self.buf[self.start] == b'\n' {
                    self.start += 1;
                }
                self.skip_lf = false;
            }
            let from = self.start + self.searched;
            let window = &self.buf[from..self.end];
            if let Some(i) = memchr::memchr2(b'\n', b'\r', window) {
                let at = from + i;
                self.searched = 0;
                let mut next = at + 1;
                if self.buf[at] == b'\r' {
                    if next < self.end {
                        if self.buf[next] == b'\n' {
                            next += 1;
                        }
                    } else {
                        self.skip_lf = true;
                    }
                }
                let line = self.start..at;
                self.start = next;
                break line;
            }
            if self.eof {
                if self.start == self.end {
                    return Ok(None);
                }
                let line = self.start..self.end;
                self.start = self.end;
                self.searched = 0;
                break line;
            }
            let pending = self.end - self.start;
            self.searched = pending;
            if pending > self.max_line {
                return Err(LineError::TooLong {
                    line: self.number + 1,
                    limit: self.max_line,
                });
            }
            self.fill()?;
        };
        self.number += 1;
        Ok(Some((self.number, &self.buf[range])))
    }

    /// Moves the unread bytes to the front and reads more after them.
    fn fill(&mut self) -> Result<(), LineError> {
        if self.start > 0 {
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
        }
        if self.buf.len() < self.end + READ_SIZE {
            // Grows with the data read: one long line costs its length.
            self.buf.resize(self.end + READ_SIZE, 0);
        }
        loop {
            match self.inner.read(&mut self.buf[self.end..]) {
                Ok(0) => {
                    self.eof = true;
                    return Ok(());
                }
                Ok(n) => {
                    self.end += n;
                    return Ok(());
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(LineError::Io(e)),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    fn all(bytes: &[u8]) -> Vec<&[u8]> {
        split_lines(bytes).collect()
    }

    #[test]
    fn every_line_ending_splits_alike() {
        let want: Vec<&[u8]> = vec![b"a", b"", b"b"];
        assert_eq!(all(b"a\n\nb\n"), want);
        assert_eq!(all(b"a\r\n\r\nb\r\n"), want);
        assert_eq!(all(b"a\r\rb\r"), want);
        assert_eq!(all(b"a\r\n\rb"), want);
        assert!(all(b"").is_empty());
        assert_eq!(all(b"\n"), vec![b"" as &[u8]]);
    }

    /// A reader that hands out one byte at a time, so every line ending
    /// falls across reads.
    struct Trickle<'a>(&'a [u8]);

    impl Read for Trickle<'_> {
        fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
            match (self.0.split_first(), out.first_mut()) {
                (Some((b, rest)), Some(o)) => {
                    *o = *b;
                    self.0 = rest;
                    Ok(1)
                }
                _ => Ok(0),
            }
        }
    }

    #[test]
    fn streamed_lines_match_split_lines_across_reads() {
        for text in [
            &b"a\r\nbb\rccc\n\r\n\rd"[..],
            b"\r\n",
            b"x\r",
            b"",
            b"one line",
        ] {
            let mut r = LineReader::new(Trickle(text), 100);
            let mut got = Vec::new();
            while let Some((n, l)) = r.next_line().unwrap() {
                assert_eq!(n, got.len() + 1);
                got.push(l.to_vec());
            }
            let want: Vec<Vec<u8>> = split_lines(text).map(<[u8]>::to_vec).collect();
            assert_eq!(got, want, "{text:?}");
            assert_eq!(r.line_number(), want.len());
        }
    }

    #[test]
    fn a_line_past_the_limit_is_refused_with_its_number() {
        let mut text = b"short\n".to_vec();
        text.extend(std::iter::repeat_n(b'x', 1_000_000));
        let mut r = LineReader::new(text.as_slice(), 1000);
        assert_eq!(r.next_line().unwrap(), Some((1, &b"short"[..])));
        match r.next_line() {
            Err(LineError::TooLong {
                line: 2,
                limit: 1000,
            }) => {}
            other => panic!("{other:?}"),
        }
    }
}
