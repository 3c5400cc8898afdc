//! Reading and writing the files a user names: one place for how a file is opened (gzip or
//! not) and for how a result is published (atomically, as an ordinary file).
//!
//! In: paths. Out: readers that gunzip on the fly and drop a leading UTF-8 byte order mark
//! ([`open_input`], and [`read_text`] for a whole text file), and writers that never leave a
//! half-written file behind ([`write_atomic`], [`AtomicFile`]). CSV cells are read in [`csv`],
//! XML written in [`xml`].

pub mod csv;
pub mod xml;

use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

/// The first two bytes of every gzip member (RFC 1952).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// The UTF-8 encoding of U+FEFF, which Windows editors and spreadsheet programs put before
/// the first character of a text file.
pub const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// A file opened for reading by [`open_input`].
pub struct Input {
    /// The content, decompressed when the file is gzip, without a leading byte order mark.
    pub reader: Box<dyn BufRead>,
    /// Whether the file started with gzip's magic bytes (an error while reading is then
    /// likely a broken gzip stream).
    pub gzip: bool,
}

/// Opens `path` for reading, gunzipping it on the fly when it starts with the gzip magic
/// bytes (whatever its name; multi-member streams are read to the end). A UTF-8 byte order
/// mark at the start of the (decompressed) content is dropped: every reader of the crate
/// comes here, so no parser sees one.
pub fn open_input(path: &Path) -> std::io::Result<Input> {
    let file = std::fs::File::open(path)?;
    let mut raw = BufReader::with_capacity(1 << 16, file);
    let gzip = raw.fill_buf()?.starts_with(&GZIP_MAGIC);
    let reader: Box<dyn BufRead> = if gzip {
        Box::new(BufReader::with_capacity(
            1 << 16,
            WithoutBom::new(flate2::bufread::MultiGzDecoder::new(raw)),
        ))
    } else {
        Box::new(BufReader::with_capacity(1 << 16, WithoutBom::new(raw)))
    };
    Ok(Input { reader, gzip })
}

/// A reader that passes on what `inner` yields less a UTF-8 byte order mark at its start.
///
/// The check waits for the first read, so that a broken gzip stream fails while the caller
/// reads (and knows to call it a gzip error), not while the file is opened; and it gathers
/// three bytes first, since a decoder or a pipe may hand them over one at a time.
struct WithoutBom<R> {
    inner: R,
    /// The first bytes of `inner`, until they are handed on.
    head: [u8; 3],
    head_len: usize,
    /// How much of `head` was handed on (or skipped, when it is the mark).
    head_pos: usize,
    checked: bool,
}

impl<R: Read> WithoutBom<R> {
    fn new(inner: R) -> WithoutBom<R> {
        WithoutBom {
            inner,
            head: [0; 3],
            head_len: 0,
            head_pos: 0,
            checked: false,
        }
    }
}

impl<R: Read> Read for WithoutBom<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if !self.checked {
            while self.head_len < self.head.len() {
                match self.inner.read(&mut self.head[self.head_len..]) {
                    Ok(0) => break,
                    Ok(n) => self.head_len += n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => return Err(e),
                }
            }
            self.checked = true;
            if self.head[..self.head_len] == *UTF8_BOM {
                self.head_pos = self.head_len;
            }
        }
        if self.head_pos < self.head_len {
            let n = (self.head_len - self.head_pos).min(buf.len());
            buf[..n].copy_from_slice(&self.head[self.head_pos..self.head_pos + n]);
            self.head_pos += n;
            return Ok(n);
        }
        self.inner.read(buf)
    }
}

/// A text file that could not be read, with its path (and line, when it is not UTF-8).
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: not a valid gzip stream: {message}", path.display())]
    Gzip { path: PathBuf, message: String },
    #[error("{}:{line}: not UTF-8 text", path.display())]
    NotUtf8 {
        path: PathBuf,
        /// 1-based line of the first byte that is not UTF-8.
        line: usize,
    },
}

impl ReadError {
    /// The file that could not be read.
    pub fn path(&self) -> &Path {
        match self {
            ReadError::Io { path, .. }
            | ReadError::Gzip { path, .. }
            | ReadError::NotUtf8 { path, .. } => path,
        }
    }
}

/// Reads a whole text file through [`open_input`]: gunzipped when it is gzip, without a
/// leading byte order mark, and checked to be UTF-8.
pub fn read_text(path: &Path) -> Result<String, ReadError> {
    let io = |source| ReadError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut input = open_input(path).map_err(io)?;
    let mut raw = Vec::new();
    input
        .reader
        .read_to_end(&mut raw)
        .map_err(|e| match input.gzip {
            true => ReadError::Gzip {
                path: path.to_path_buf(),
                message: e.to_string(),
            },
            false => io(e),
        })?;
    String::from_utf8(raw).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        ReadError::NotUtf8 {
            path: path.to_path_buf(),
            line: 1 + valid.iter().filter(|&&b| b == b'\n').count(),
        }
    })
}

/// A file that could not be written, with its path.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {source}")]
pub struct WriteError {
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

/// What a writer does about missing folders above the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Folders {
    /// Creates them.
    Create,
    /// Fails: the caller's folder must already be there.
    MustExist,
}

/// Writes `bytes` to `path` atomically: into a temporary file in the same folder, then renamed
/// over `path`. Creates missing parent folders. Paths ending in `.gz` are gzip-compressed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    write_atomic_in(path, bytes, Folders::Create)
}

/// [`write_atomic`], saying what to do about missing parent folders.
pub fn write_atomic_in(path: &Path, bytes: &[u8], folders: Folders) -> Result<(), WriteError> {
    let mut file = AtomicFile::open(path, folders)?;
    file.write_all(bytes).map_err(|e| file.error(e))?;
    file.commit()
}

/// A file written as a stream and published atomically, like [`write_atomic`]: the content
/// goes into a temporary file beside `path`, which [`AtomicFile::commit`] renames over `path`.
/// Dropped without a commit, the temporary file is removed and `path` is left as it was.
///
/// The published file has the mode of any file the user creates (0666 less the umask, so
/// 0644 under the usual umask 022), not the private 0600 of a temporary file.
///
/// A symbolic link is followed: the file it names is replaced and the link stays. A special
/// file (a FIFO, a device such as `/dev/null` or `/dev/stdout`) is written in place, since a
/// rename would put a regular file where it was.
pub struct AtomicFile {
    path: PathBuf,
    /// Where the temporary file is renamed to: `path` with its symbolic links followed.
    target: PathBuf,
    out: Sink,
}

enum Sink {
    Plain(BufWriter<Target>),
    Gzip(flate2::write::GzEncoder<BufWriter<Target>>),
}

/// What the bytes go into.
enum Target {
    Temporary(tempfile::NamedTempFile),
    Special(std::fs::File),
}

impl Write for Target {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            Target::Temporary(f) => f.write(buf),
            Target::Special(f) => f.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Target::Temporary(f) => f.flush(),
            Target::Special(f) => f.flush(),
        }
    }
}

/// `path` with its symbolic links followed (also a dangling one: the file it would name).
fn follow_links(path: &Path) -> PathBuf {
    let mut p = path.to_path_buf();
    // Bounded like the kernel's own limit, so a link cycle ends.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => match std::fs::read_link(&p) {
                Ok(t) if t.is_absolute() => p = t,
                Ok(t) => p = p.parent().unwrap_or(Path::new(".")).join(t),
                Err(_) => break,
            },
            _ => break,
        }
    }
    p
}

impl AtomicFile {
    /// Starts writing `path` (parent folders are created; `.gz` paths are gzip-compressed).
    pub fn create(path: &Path) -> Result<AtomicFile, WriteError> {
        AtomicFile::open(path, Folders::Create)
    }

    /// Starts writing `path`, creating missing parent folders or not as `folders` says
    /// (`.gz` paths are gzip-compressed).
    pub fn open(path: &Path, folders: Folders) -> Result<AtomicFile, WriteError> {
        let err = |source| WriteError {
            path: path.to_path_buf(),
            source,
        };
        let target = follow_links(path);
        let special = std::fs::metadata(&target).is_ok_and(|m| !m.is_file() && !m.is_dir());
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if folders == Folders::Create && !special {
            std::fs::create_dir_all(dir).map_err(err)?;
        }
        let file = if special {
            Target::Special(
                std::fs::OpenOptions::new()
                    .write(true)
                    .open(&target)
                    .map_err(err)?,
            )
        } else {
            Target::Temporary(temporary_in(dir).map_err(err)?)
        };
        let tmp = BufWriter::with_capacity(1 << 16, file);
        let out = if path.extension().is_some_and(|e| e == "gz") {
            Sink::Gzip(flate2::write::GzEncoder::new(
                tmp,
                flate2::Compression::default(),
            ))
        } else {
            Sink::Plain(tmp)
        };
        Ok(AtomicFile {
            path: path.to_path_buf(),
            target,
            out,
        })
    }

    /// The error for `source`, naming this file.
    pub fn error(&self, source: std::io::Error) -> WriteError {
        WriteError {
            path: self.path.clone(),
            source,
        }
    }

    /// Flushes, syncs and renames the temporary file over the target path (a special file:
    /// flushes what was written into it).
    pub fn commit(self) -> Result<(), WriteError> {
        let path = self.path;
        let target = self.target;
        let err = |source| WriteError {
            path: path.clone(),
            source,
        };
        let buffered = match self.out {
            Sink::Plain(b) => b,
            Sink::Gzip(gz) => gz.finish().map_err(err)?,
        };
        match buffered.into_inner().map_err(|e| err(e.into_error()))? {
            Target::Temporary(tmp) => {
                tmp.as_file().sync_all().map_err(err)?;
                tmp.persist(&target).map_err(|e| err(e.error))?;
            }
            Target::Special(mut f) => f.flush().map_err(err)?,
        }
        Ok(())
    }
}

/// A new temporary file in `dir` that will have the mode of any file the user creates.
fn temporary_in(dir: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    // Asking for 0666 at creation lets the kernel apply the umask, as for any new file;
    // tempfile's default 0600 would survive the rename.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.out {
            Sink::Plain(w) => w.write(buf),
            Sink::Gzip(w) => w.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.out {
            Sink::Plain(w) => w.flush(),
            Sink::Gzip(w) => w.flush(),
        }
    }
}

/// Whether two paths name the same file; the second need not exist yet. Existing files are
/// compared by device and inode (so a hard link or a symlink to an input is the input);
/// otherwise the paths are compared after resolving their folders, so `./a.csv` and `a.csv`
/// are the same.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    let resolve = |p: &Path| {
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::canonicalize(dir)
            .ok()
            .map(|d| d.join(p.file_name().unwrap_or_default()))
    };
    match (resolve(a), resolve(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    #[test]
    fn gzip_is_recognized_by_its_bytes_not_its_name() {
        let dir = tempfile::tempdir().unwrap();
        let packed = dir.path().join("log.txt");
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(b"hello\n").unwrap();
        std::fs::write(&packed, gz.finish().unwrap()).unwrap();
        let plain = dir.path().join("log.gz");
        std::fs::write(&plain, "plain\n").unwrap();
        for (path, gzip, text) in [(&packed, true, "hello\n"), (&plain, false, "plain\n")] {
            let mut input = open_input(path).unwrap();
            assert_eq!(input.gzip, gzip);
            let mut got = String::new();
            input.reader.read_to_string(&mut got).unwrap();
            assert_eq!(got, text);
        }
    }

    #[test]
    fn one_leading_byte_order_mark_is_dropped_plain_or_gzip() {
        let dir = tempfile::tempdir().unwrap();
        let plain = dir.path().join("marked.txt");
        std::fs::write(&plain, b"\xEF\xBB\xBF\xEF\xBB\xBF1\n").unwrap();
        let packed = dir.path().join("marked.gz");
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(b"\xEF\xBB\xBFin:a\n").unwrap();
        std::fs::write(&packed, gz.finish().unwrap()).unwrap();
        let short = dir.path().join("short.txt");
        std::fs::write(&short, b"\xEF\xBB").unwrap();
        for (path, want) in [
            (&plain, &b"\xEF\xBB\xBF1\n"[..]),
            (&packed, b"in:a\n"),
            (&short, b"\xEF\xBB"),
        ] {
            let mut got = Vec::new();
            open_input(path)
                .unwrap()
                .reader
                .read_to_end(&mut got)
                .unwrap();
            assert_eq!(got, want, "{}", path.display());
        }
        assert_eq!(read_text(&packed).unwrap(), "in:a\n");
    }

    /// A reader that hands over one byte per call, as a pipe or a decoder may.
    struct Trickle<'a>(&'a [u8]);

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = self.0.len().min(buf.len()).min(1);
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    #[test]
    fn a_byte_order_mark_read_a_byte_at_a_time_is_dropped() {
        for (input, want) in [
            (&b"\xEF\xBB\xBFab"[..], &b"ab"[..]),
            (b"\xEFab", b"\xEFab"),
            (b"a", b"a"),
            (b"", b""),
        ] {
            let mut got = Vec::new();
            WithoutBom::new(Trickle(input))
                .read_to_end(&mut got)
                .unwrap();
            assert_eq!(got, want, "{input:?}");
        }
    }

    #[test]
    fn text_that_is_not_utf8_names_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("latin1.txt");
        std::fs::write(&path, b"a\nb\n\xE9t\xE9\n").unwrap();
        let e = read_text(&path).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("{}:3: not UTF-8 text", path.display())
        );
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        std::fs::write(&path, "old").unwrap();
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"half").unwrap();
        drop(file);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let missing = dir.path().join("no/such/out.txt");
        let e = write_atomic_in(&missing, b"x", Folders::MustExist).unwrap_err();
        assert_eq!(e.path, missing);
        write_atomic(&missing, b"x").unwrap();
        assert_eq!(std::fs::read_to_string(&missing).unwrap(), "x");
    }
}
