//! The fuzz harness's mutator: seeded, deterministic damage to an input
//! file, of the kinds hostile and careless files carry. One [`mutate`]
//! serves every reader; [`Mutation`] lists what it does.

#![allow(dead_code)]

use std::io::Write;

use bump::rng::Rng;

/// One kind of damage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mutation {
    /// A byte set to a random value.
    ByteFlip,
    /// One bit of a byte flipped.
    BitFlip,
    /// The input cut at a random point.
    Truncate,
    /// A line removed.
    DeleteLine,
    /// A line repeated (once, or many times).
    DuplicateLine,
    /// Two lines swapped.
    SwapLines,
    /// A line's columns shifted: spaces inserted or removed.
    ShiftColumns,
    /// A number replaced by a huge one (or a tiny, or one past `u64`).
    HugeNumber,
    /// A number replaced by `NaN`, `inf`, `-inf`.
    NotFinite,
    /// Bytes outside ASCII inserted: valid UTF-8, invalid UTF-8, NUL and
    /// control bytes.
    NonAscii,
    /// Line endings changed to CR or CRLF (all or one).
    LineEndings,
    /// A whole number (a count, an index) replaced by a lie: 0, 10⁹, 10¹⁸,
    /// 2⁶⁴, −1.
    LyingCount,
    /// A line made very long.
    LongLine,
    /// The input gzipped (after any other damage).
    Gzip,
    /// Random bytes behind a gzip header, or a gzip stream cut short.
    GzipJunk,
    /// A gzip bomb: a small file that expands a thousandfold.
    GzipBomb,
}

/// Largest mutant, bytes: mutations that lengthen (long lines, repeated
/// lines) stop here, so stacked ones cannot grow without end.
pub const MAX_MUTANT: usize = 256 << 10;

/// Every mutation, for sampling.
pub const ALL: [Mutation; 16] = [
    Mutation::ByteFlip,
    Mutation::BitFlip,
    Mutation::Truncate,
    Mutation::DeleteLine,
    Mutation::DuplicateLine,
    Mutation::SwapLines,
    Mutation::ShiftColumns,
    Mutation::HugeNumber,
    Mutation::NotFinite,
    Mutation::NonAscii,
    Mutation::LineEndings,
    Mutation::LyingCount,
    Mutation::LongLine,
    Mutation::Gzip,
    Mutation::GzipJunk,
    Mutation::GzipBomb,
];

/// A random index below `n` (0 when `n` is 0).
pub fn below(rng: &mut Rng, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (rng.next_u64() % n as u64) as usize
    }
}

/// True one time in `n`.
pub fn one_in(rng: &mut Rng, n: u64) -> bool {
    rng.next_u64().is_multiple_of(n)
}

/// Byte ranges of the lines of `data` (terminators excluded).
fn line_spans(data: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, &b) in data.iter().enumerate() {
        if b == b'\n' {
            out.push((start, i));
            start = i + 1;
        }
    }
    if start < data.len() {
        out.push((start, data.len()));
    }
    out
}

/// Byte ranges of the numbers in `data` (optional sign, digits, a point,
/// an exponent).
fn number_spans(data: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < data.len() {
        let start = i;
        if (data[i] == b'-' || data[i] == b'+') && data.get(i + 1).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        if data[i].is_ascii_digit() {
            while i < data.len() && (data[i].is_ascii_digit() || data[i] == b'.') {
                i += 1;
            }
            if i < data.len() && (data[i] == b'e' || data[i] == b'E') {
                i += 1;
                while i < data.len() && (data[i].is_ascii_digit() || data[i] == b'-') {
                    i += 1;
                }
            }
            out.push((start, i));
        } else {
            i = start + 1;
        }
    }
    out
}

/// Replaces a random number of `data` with one of `with`, keeping its
/// width where the replacement fits (fixed columns stay aligned) when
/// `rng` says so.
fn replace_number(rng: &mut Rng, data: &mut Vec<u8>, with: &[&str], whole_only: bool) {
    let spans: Vec<(usize, usize)> = number_spans(data)
        .into_iter()
        .filter(|&(a, b)| !whole_only || !data[a..b].contains(&b'.'))
        .collect();
    if spans.is_empty() {
        return;
    }
    let (a, b) = spans[below(rng, spans.len())];
    let mut new = with[below(rng, with.len())].as_bytes().to_vec();
    if one_in(rng, 2) && new.len() < b - a {
        let mut padded = vec![b' '; b - a - new.len()];
        padded.extend(new);
        new = padded;
    }
    data.splice(a..b, new);
}

/// gzip of `data`.
pub fn gzip(data: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    let _ = e.write_all(data);
    e.finish().unwrap_or_default()
}

/// Applies `m` to `data`. The result may be anything, as a hostile file
/// may be.
pub fn apply(rng: &mut Rng, m: Mutation, data: &mut Vec<u8>) {
    let lines = line_spans(data);
    let pick_line = |rng: &mut Rng| lines.get(below(rng, lines.len())).copied();
    match m {
        Mutation::ByteFlip => {
            if !data.is_empty() {
                let i = below(rng, data.len());
                data[i] = rng.next_u64() as u8;
            }
        }
        Mutation::BitFlip => {
            if !data.is_empty() {
                let i = below(rng, data.len());
                data[i] ^= 1 << (rng.next_u64() % 8);
            }
        }
        Mutation::Truncate => {
            let n = below(rng, data.len() + 1);
            data.truncate(n);
        }
        Mutation::DeleteLine => {
            if let Some((a, b)) = pick_line(rng) {
                let end = (b + 1).min(data.len());
                data.drain(a..end);
            }
        }
        Mutation::DuplicateLine => {
            if let Some((a, b)) = pick_line(rng) {
                let mut line = data[a..b].to_vec();
                line.push(b'\n');
                let times = if one_in(rng, 8) {
                    1 + below(rng, 300)
                } else {
                    1
                };
                let times = times.min(MAX_MUTANT / line.len().max(1)).max(1);
                let copies: Vec<u8> = line
                    .iter()
                    .copied()
                    .cycle()
                    .take(line.len() * times)
                    .collect();
                let at = (b + 1).min(data.len());
                data.splice(at..at, copies);
            }
        }
        Mutation::SwapLines => {
            if lines.len() >= 2 {
                let (i, j) = (below(rng, lines.len()), below(rng, lines.len()));
                let (i, j) = (i.min(j), i.max(j));
                if i != j {
                    let (a, b) = lines[i];
                    let (c, d) = lines[j];
                    let mut out = data[..a].to_vec();
                    out.extend_from_slice(&data[c..d]);
                    out.extend_from_slice(&data[b..c]);
                    out.extend_from_slice(&data[a..b]);
                    out.extend_from_slice(&data[d..]);
                    *data = out;
                }
            }
        }
        Mutation::ShiftColumns => {
            if let Some((a, b)) = pick_line(rng) {
                let at = a + below(rng, b - a + 1);
                let n = 1 + below(rng, 3);
                if one_in(rng, 2) {
                    data.splice(at..at, std::iter::repeat_n(b' ', n));
                } else {
                    let end = (at + n).min(b);
                    data.drain(at..end);
                }
            }
        }
        Mutation::HugeNumber => replace_number(
            rng,
            data,
            &[
                "1e308",
                "-1e308",
                "1e309",
                "99999999999999999999",
                "1e-320",
                "18446744073709551616",
                "9223372036854775807",
                "-9223372036854775808",
                "1e19",
                "4294967296",
            ],
            false,
        ),
        Mutation::NotFinite => replace_number(
            rng,
            data,
            &["NaN", "nan", "inf", "-inf", "Infinity", "-0"],
            false,
        ),
        Mutation::NonAscii => {
            let inserts: [&[u8]; 8] = [
                "é".as_bytes(),
                "\u{FFFD}".as_bytes(),
                "€€".as_bytes(),
                b"\xff",
                b"\xc3",
                b"\x00",
                b"\x01\x1b",
                b"\xf0\x9f\x98",
            ];
            let what = inserts[below(rng, inserts.len())];
            let at = below(rng, data.len() + 1);
            if one_in(rng, 2) && at < data.len() {
                let end = (at + what.len()).min(data.len());
                data.splice(at..end, what.iter().copied());
            } else {
                data.splice(at..at, what.iter().copied());
            }
        }
        Mutation::LineEndings => {
            let to: &[u8] = if one_in(rng, 2) { b"\r" } else { b"\r\n" };
            if one_in(rng, 4) {
                if let Some((_, b)) = pick_line(rng)
                    && b < data.len()
                {
                    data.splice(b..b + 1, to.iter().copied());
                }
            } else {
                let mut out = Vec::with_capacity(data.len() * 2);
                for &c in data.iter() {
                    if c == b'\n' {
                        out.extend_from_slice(to);
                    } else {
                        out.push(c);
                    }
                }
                *data = out;
            }
        }
        Mutation::LyingCount => replace_number(
            rng,
            data,
            &[
                "0",
                "1000000000",
                "1000000000000000000",
                "18446744073709551616",
                "-1",
                "999",
                "2147483648",
            ],
            true,
        ),
        Mutation::LongLine => {
            if let Some((a, b)) = pick_line(rng) {
                let unit: Vec<u8> = if b > a {
                    data[a..b].to_vec()
                } else {
                    b"x ".to_vec()
                };
                let times = (50 + below(rng, 500))
                    .min(MAX_MUTANT / unit.len().max(1))
                    .max(1);
                let long: Vec<u8> = unit
                    .iter()
                    .copied()
                    .cycle()
                    .take(unit.len() * times)
                    .collect();
                data.splice(a..b, long);
            }
        }
        Mutation::Gzip => *data = gzip(data),
        Mutation::GzipJunk => {
            if one_in(rng, 2) {
                let mut junk = vec![0x1f, 0x8b, 8, 0];
                junk.extend((0..below(rng, 200)).map(|_| rng.next_u64() as u8));
                *data = junk;
            } else {
                let z = gzip(data);
                let cut = below(rng, z.len() + 1);
                *data = z[..cut].to_vec();
                if one_in(rng, 2) {
                    data.extend_from_slice(b"trailing junk");
                }
            }
        }
        Mutation::GzipBomb => {
            let size = 1 << (16 + below(rng, 6));
            let fill: Vec<u8> = match below(rng, 4) {
                0 => vec![b' '; size],
                1 => vec![b'\n'; size],
                2 => vec![0; size],
                _ => {
                    // A line of the input, again and again.
                    let (a, b) = pick_line(rng).unwrap_or((0, 0));
                    let mut line = data[a..b].to_vec();
                    line.push(b'\n');
                    line.iter().copied().cycle().take(size).collect()
                }
            };
            *data = gzip(&fill);
        }
    }
}

/// `seed` damaged by one to three mutations (gzip ones last, as files are
/// gzipped after they are written), with the mutations applied.
pub fn mutate(rng: &mut Rng, seed: &[u8]) -> (Vec<u8>, Vec<Mutation>) {
    let mut data = seed.to_vec();
    let n = 1 + below(rng, 3);
    let mut applied: Vec<Mutation> = (0..n).map(|_| ALL[below(rng, ALL.len())]).collect();
    // Damage to gzip data is mostly damage to its header: do it to the
    // text, then compress.
    applied.sort_by_key(|m| matches!(m, Mutation::Gzip | Mutation::GzipJunk | Mutation::GzipBomb));
    for &m in &applied {
        apply(rng, m, &mut data);
        data.truncate(MAX_MUTANT);
    }
    (data, applied)
}
