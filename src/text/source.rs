//! Files as byte streams, gunzipped when they start with the gzip magic
//! bytes (whatever their name), with a limit on the decompressed size: a
//! small gzip can expand a thousandfold, and no reader may be made to hold,
//! or even scan, more than the limit says.
//!
//! [`TextSource`] streams: a gzipped file is decompressed on a thread of
//! its own, a chunk ahead of the reader, so that gunzip and parse run on
//! two cores at once. [`read_limited`] reads a whole (small) file into
//! memory under the same limit.

use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;

use flate2::read::MultiGzDecoder;
use thiserror::Error;

/// The decompressed size a reader accepts unless told otherwise: 2 GiB,
/// above the largest mmCIF file in the PDB (about 1 GiB uncompressed).
pub const DEFAULT_DECOMPRESSED_LIMIT: u64 = 2 << 30;

/// How a gzipped stream ends: decompressed in chunks of this size.
const CHUNK: usize = 1 << 20;

/// Chunks decompressed ahead of the reader.
const AHEAD: usize = 2;

/// Why a file's bytes could not be had.
#[derive(Debug, Error)]
pub enum SourceError {
    /// Opening or reading failed.
    #[error("cannot read: {0}")]
    Io(std::io::Error),
    /// The gzip stream is damaged.
    #[error("cannot decompress gzip data: {0}")]
    Gzip(std::io::Error),
    /// The data decompress to more than the limit.
    #[error(
        "decompresses to more than {} (the limit; a larger one can be set with --max-decompressed or BUMP_MAX_DECOMPRESSED)",
        format_bytes(*limit)
    )]
    TooLarge {
        /// The limit, bytes.
        limit: u64,
    },
}

impl SourceError {
    /// The source error inside an I/O error from [`TextSource`]'s `read`,
    /// or the I/O error itself.
    pub fn from_io(e: std::io::Error) -> Self {
        if e.get_ref()
            .and_then(|i| i.downcast_ref::<Marker>())
            .is_some()
        {
            match e.into_inner().and_then(|i| i.downcast::<Marker>().ok()) {
                Some(m) => return m.0,
                None => return SourceError::Io(std::io::Error::other("unknown")),
            }
        }
        SourceError::Io(e)
    }
}

/// A [`SourceError`] carried through `std::io::Read`.
#[derive(Debug, Error)]
#[error("{0}")]
struct Marker(SourceError);

fn carried(e: SourceError) -> std::io::Error {
    std::io::Error::other(Marker(e))
}

/// A byte stream: a plain file read as it is, a gzipped one decompressed
/// (on a thread of its own for files; in line for bytes in memory).
pub struct TextSource<'a> {
    inner: Inner<'a>,
    gzip: bool,
}

impl std::fmt::Debug for TextSource<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TextSource")
            .field("gzip", &self.gzip)
            .finish()
    }
}

enum Inner<'a> {
    Plain(Box<dyn Read + 'a>),
    Gzip(Limited<MultiGzDecoder<&'a [u8]>>),
    Threaded(Threaded),
}

/// A gzip stream decompressed on another thread.
struct Threaded {
    rx: Option<Receiver<Result<Vec<u8>, SourceError>>>,
    chunk: Vec<u8>,
    at: usize,
    thread: Option<JoinHandle<()>>,
}

impl Drop for Threaded {
    fn drop(&mut self) {
        // Closing the channel stops the thread at its next chunk.
        self.rx = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Read for Threaded {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        while self.at == self.chunk.len() {
            let Some(rx) = &self.rx else {
                return Ok(0);
            };
            match rx.recv() {
                Ok(Ok(chunk)) => {
                    self.chunk = chunk;
                    self.at = 0;
                }
                Ok(Err(e)) => return Err(carried(e)),
                // The thread has sent everything, or died.
                Err(_) => {
                    self.rx = None;
                    if let Some(t) = self.thread.take()
                        && t.join().is_err()
                    {
                        return Err(std::io::Error::other("the gunzip thread failed"));
                    }
                    return Ok(0);
                }
            }
        }
        let n = out.len().min(self.chunk.len() - self.at);
        out[..n].copy_from_slice(&self.chunk[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// A reader that fails once more than `limit` bytes came out of it.
struct Limited<R> {
    inner: R,
    read: u64,
    limit: u64,
}

impl<R: Read> Read for Limited<R> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        let n = self
            .inner
            .read(out)
            .map_err(|e| carried(SourceError::Gzip(e)))?;
        self.read += n as u64;
        if self.read > self.limit {
            return Err(carried(SourceError::TooLarge { limit: self.limit }));
        }
        Ok(n)
    }
}

impl Read for TextSource<'_> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        match &mut self.inner {
            Inner::Plain(r) => r.read(out),
            Inner::Gzip(r) => r.read(out),
            Inner::Threaded(r) => r.read(out),
        }
    }
}

const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

impl TextSource<'static> {
    /// Opens `path`, decompressing on a thread of its own when it starts
    /// with the gzip magic bytes; at most `limit` decompressed bytes.
    ///
    /// # Errors
    /// [`SourceError::Io`] when the file cannot be opened or read.
    pub fn open(path: &Path, limit: u64) -> Result<Self, SourceError> {
        let mut file = File::open(path).map_err(SourceError::Io)?;
        let mut magic = [0u8; 2];
        let mut got = 0;
        while got < 2 {
            match file.read(&mut magic[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(SourceError::Io(e)),
            }
        }
        let head = std::io::Cursor::new(magic[..got].to_vec());
        let whole = head.chain(file);
        if got == 2 && magic == GZIP_MAGIC {
            let (tx, rx) = sync_channel(AHEAD);
            let thread = std::thread::Builder::new()
                .name("gunzip".into())
                .spawn(move || gunzip(whole, limit, &tx))
                .map_err(SourceError::Io)?;
            Ok(Self {
                inner: Inner::Threaded(Threaded {
                    rx: Some(rx),
                    chunk: Vec::new(),
                    at: 0,
                    thread: Some(thread),
                }),
                gzip: true,
            })
        } else {
            Ok(Self {
                inner: Inner::Plain(Box::new(whole)),
                gzip: false,
            })
        }
    }
}

impl<'a> TextSource<'a> {
    /// Bytes in memory, decompressed (in line) when they start with the
    /// gzip magic bytes; at most `limit` decompressed bytes.
    pub fn from_bytes(bytes: &'a [u8], limit: u64) -> Self {
        if bytes.starts_with(&GZIP_MAGIC) {
            Self {
                inner: Inner::Gzip(Limited {
                    inner: MultiGzDecoder::new(bytes),
                    read: 0,
                    limit,
                }),
                gzip: true,
            }
        } else {
            Self {
                inner: Inner::Plain(Box::new(bytes)),
                gzip: false,
            }
        }
    }

    /// True when the bytes are being gunzipped.
    pub fn is_gzip(&self) -> bool {
        self.gzip
    }

    /// Reads everything that is left.
    ///
    /// # Errors
    /// As [`read_limited`].
    pub fn read_all(mut self) -> Result<Vec<u8>, SourceError> {
        let mut out = Vec::new();
        self.read_to_end(&mut out).map_err(SourceError::from_io)?;
        Ok(out)
    }
}

/// The gzip thread: decompresses `input` in chunks, sending each, until the
/// end, an error, the limit, or the reader hangs up.
fn gunzip(input: impl Read, limit: u64, tx: &SyncSender<Result<Vec<u8>, SourceError>>) {
    let mut decoder = MultiGzDecoder::new(BufReader::with_capacity(CHUNK, input));
    let mut total: u64 = 0;
    loop {
        let mut chunk = vec![0u8; CHUNK];
        let mut filled = 0;
        let result = loop {
            match decoder.read(&mut chunk[filled..]) {
                Ok(0) => break Ok(true),
                Ok(n) => {
                    filled += n;
                    if filled == chunk.len() {
                        break Ok(false);
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => break Err(e),
            }
        };
        total += filled as u64;
        if total > limit {
            let _ = tx.send(Err(SourceError::TooLarge { limit }));
            return;
        }
        chunk.truncate(filled);
        let ended = match result {
            Ok(ended) => ended,
            Err(e) => {
                if filled > 0 && tx.send(Ok(chunk)).is_err() {
                    return;
                }
                let _ = tx.send(Err(SourceError::Gzip(e)));
                return;
            }
        };
        if filled > 0 && tx.send(Ok(chunk)).is_err() {
            return;
        }
        if ended {
            return;
        }
    }
}

/// The whole of `path`, gunzipped when it starts with the gzip magic bytes,
/// at most `limit` bytes once decompressed.
///
/// # Errors
/// [`SourceError`]: unreadable, damaged gzip data, or past the limit.
pub fn read_limited(path: &Path, limit: u64) -> Result<Vec<u8>, SourceError> {
    let raw = std::fs::read(path).map_err(SourceError::Io)?;
    if !raw.starts_with(&GZIP_MAGIC) {
        return Ok(raw);
    }
    TextSource::from_bytes(&raw, limit).read_all()
}

/// A size for messages: `2 GiB`, `1.5 MiB`, `512 bytes`.
pub fn format_bytes(n: u64) -> String {
    const UNITS: [(&str, u64); 4] = [
        ("TiB", 1 << 40),
        ("GiB", 1 << 30),
        ("MiB", 1 << 20),
        ("KiB", 1 << 10),
    ];
    for (unit, size) in UNITS {
        if n >= size {
            let v = n as f64 / size as f64;
            return if n.is_multiple_of(size) {
                format!("{} {unit}", n / size)
            } else {
                format!("{v:.1} {unit}")
            };
        }
    }
    format!("{n} bytes")
}

/// Parses a size: a whole number of bytes, optionally followed by a unit
/// (`K`, `M`, `G`, `T`, with or without `iB`/`B`, any case; all binary).
///
/// # Errors
/// A message naming the text.
pub fn parse_byte_size(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, unit) = t.split_at(digits);
    let n: u64 = number
        .parse()
        .map_err(|_| format!("`{s}` is not a size (a whole number, then K, M, G or T)"))?;
    let shift = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kb" | "kib" => 10,
        "m" | "mb" | "mib" => 20,
        "g" | "gb" | "gib" => 30,
        "t" | "tb" | "tib" => 40,
        _ => return Err(format!("`{s}`: unknown unit (K, M, G or T)")),
    };
    n.checked_mul(1 << shift)
        .ok_or_else(|| format!("`{s}` is too large"))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use std::io::Write;

    use super::*;

    fn gz(data: &[u8]) -> Vec<u8> {
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        e.write_all(data).unwrap();
        e.finish().unwrap()
    }

    #[test]
    fn gzip_in_memory_is_read_under_the_limit() {
        let data = vec![b' '; 100_000];
        let z = gz(&data);
        assert_eq!(
            TextSource::from_bytes(&z, 100_000).read_all().unwrap(),
            data
        );
        match TextSource::from_bytes(&z, 99_999).read_all() {
            Err(SourceError::TooLarge { limit: 99_999 }) => {}
            other => panic!("{other:?}"),
        }
        let mut junk = z.clone();
        junk.truncate(z.len() / 2);
        assert!(matches!(
            TextSource::from_bytes(&junk, 1 << 20).read_all(),
            Err(SourceError::Gzip(_))
        ));
        assert_eq!(
            TextSource::from_bytes(b"plain", 1).read_all().unwrap(),
            b"plain"
        );
    }

    #[test]
    fn gzipped_files_stream_from_their_thread() {
        let dir = std::env::temp_dir().join(format!("bump-source-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let data: Vec<u8> = (0..3_000_000u32).map(|i| (i % 251) as u8).collect();
        let mut two = gz(&data[..1_000_000]);
        two.extend(gz(&data[1_000_000..]));
        let path = dir.join("x.gz");
        std::fs::write(&path, &two).unwrap();
        let got = TextSource::open(&path, 1 << 30)
            .unwrap()
            .read_all()
            .unwrap();
        assert!(got == data, "concatenated members are read to the end");
        match TextSource::open(&path, 2_000_000).unwrap().read_all() {
            Err(SourceError::TooLarge { limit: 2_000_000 }) => {}
            other => panic!("{other:?}"),
        }
        // A reader that stops early lets the thread go.
        let mut early = TextSource::open(&path, 1 << 30).unwrap();
        let mut some = [0u8; 10];
        early.read_exact(&mut some).unwrap();
        drop(early);
        let plain = dir.join("p.txt");
        std::fs::write(&plain, b"x").unwrap();
        let s = TextSource::open(&plain, 0).unwrap();
        assert!(!s.is_gzip());
        assert_eq!(s.read_all().unwrap(), b"x");
        assert_eq!(read_limited(&path, 1 << 30).unwrap().len(), data.len());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn sizes_read_and_print() {
        assert_eq!(parse_byte_size("2GiB"), Ok(2 << 30));
        assert_eq!(parse_byte_size("512m"), Ok(512 << 20));
        assert_eq!(parse_byte_size("100"), Ok(100));
        assert!(parse_byte_size("1.5G").is_err());
        assert!(parse_byte_size("99999999999T").is_err());
        assert_eq!(format_bytes(2 << 30), "2 GiB");
        assert_eq!(format_bytes(1536 << 10), "1.5 MiB");
        assert_eq!(format_bytes(12), "12 bytes");
    }
}
