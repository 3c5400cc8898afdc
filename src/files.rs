//! Reading and writing the files a user names: one place for how a file is opened (gzip or
//! not) and for how a result is published (atomically, as an ordinary file).
//!
//! In: paths. Out: readers that gunzip on the fly and drop a leading UTF-8 byte order mark
//! ([`open_input`], and [`read_text`] for a whole text file), and writers that never leave a
//! half-written file behind ([`write_atomic`], [`AtomicFile`]). CSV cells are read in [`csv`],
//! XML written in [`xml`].

pub(crate) mod csv;
pub(crate) mod output_rule;
pub(crate) mod result_set;
pub(crate) mod xml;

pub(crate) use output_rule::allow_replacing;
pub use output_rule::RuleError;
pub(crate) use result_set::ResultSet;
pub use result_set::ResultSetError;

use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

/// Paths removed when a termination signal ends the program ([`crate::signals`]): staging
/// folders and work folders that a destructor would otherwise have removed.
static TEMPORARIES: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Removes `path` (a file or a folder with its content) if a termination signal ends the
/// program before [`keep_on_signal`].
pub(crate) fn remove_on_signal(path: &Path) {
    TEMPORARIES
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(path.to_path_buf());
    crate::signals::on_termination(remove_temporaries);
    // Registered after the clean-up read the list: this thread removes it itself.
    if crate::signals::terminating() {
        remove_temporaries();
    }
}

/// A temporary folder of the run's own: removed when dropped, and when a termination signal
/// ends the program first ([`remove_on_signal`]).
pub(crate) struct WorkDir {
    // Forgotten for the signal first, then removed with its TempDir.
    _on_signal: RemovedOnSignal,
    dir: tempfile::TempDir,
}

impl WorkDir {
    /// A new empty folder in the system's temporary folder (mode 0700).
    pub(crate) fn new() -> std::io::Result<WorkDir> {
        let dir = tempfile::tempdir()?;
        remove_on_signal(dir.path());
        Ok(WorkDir {
            _on_signal: RemovedOnSignal(dir.path().to_path_buf()),
            dir,
        })
    }

    /// Where it is.
    pub(crate) fn path(&self) -> &Path {
        self.dir.path()
    }
}

/// Forgets `path` for [`remove_on_signal`]: it is gone, or it is a result now.
pub(crate) fn keep_on_signal(path: &Path) {
    for list in [&TEMPORARIES, &MADE_FOLDERS] {
        list.lock()
            .unwrap_or_else(|e| e.into_inner())
            .retain(|p| p != path);
    }
}

/// Folders a run made for its results: removed, if empty by then, when a termination signal
/// ends the program before [`keep_on_signal`] (after the temporaries inside them went).
static MADE_FOLDERS: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Removes the folder `path` if it is empty once the temporaries are gone, when a termination
/// signal ends the program before [`keep_on_signal`].
pub(crate) fn remove_empty_on_signal(path: &Path) {
    MADE_FOLDERS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(path.to_path_buf());
    crate::signals::on_termination(remove_temporaries);
}

fn remove_temporaries() {
    let paths = TEMPORARIES
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .clone();
    for p in paths {
        if std::fs::symlink_metadata(&p).is_ok_and(|m| m.is_dir()) {
            let _ = std::fs::remove_dir_all(&p);
        } else {
            let _ = std::fs::remove_file(&p);
        }
    }
    let folders = MADE_FOLDERS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .clone();
    for p in folders.iter().rev() {
        let _ = std::fs::remove_dir(p);
    }
}

/// The longest line (its line break not counted) that any reader of a user's text file
/// accepts: 1 MiB. Real lines of the formats read here (log rows, mapping and names lines,
/// formulas) are a few hundred bytes; the cap keeps a file with no line break at all (a
/// corrupted log, `/dev/zero`) from filling memory before the error is found.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The largest file that is read whole into memory (scenario files, machines, mapping, names,
/// LTL and plant files): 1 GiB, far more than any of them holds in practice.
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// The first two bytes of every gzip member (RFC 1952).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// The UTF-8 encoding of U+FEFF, which Windows editors and spreadsheet programs put before
/// the first character of a text file.
pub(crate) const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// A file opened for reading by [`open_input`].
pub(crate) struct Input {
    /// The content, decompressed when the file is gzip, without a leading byte order mark.
    pub(crate) reader: Box<dyn BufRead>,
    /// Whether the file started with gzip's magic bytes (an error while reading is then
    /// likely a broken gzip stream).
    pub(crate) gzip: bool,
}

/// Opens `path` for reading, gunzipping it on the fly when it starts with the gzip magic
/// bytes (whatever its name; multi-member streams are read to the end). A UTF-8 byte order
/// mark at the start of the (decompressed) content is dropped: every reader of the crate
/// comes here, so no parser sees one.
///
/// `-` is standard input: streamed on its first opening, unless [`stdin_text_head`] cached it
/// whole before (then every opening reads the cached copy).
pub(crate) fn open_input(path: &Path) -> std::io::Result<Input> {
    let source: Box<dyn Read> = match is_stdin(path) {
        true => match STDIN.get() {
            Some(Ok(bytes)) => Box::new(std::io::Cursor::new(bytes.as_slice())),
            Some(Err(e)) => return Err(std::io::Error::other(e.clone())),
            None => Box::new(std::io::stdin()),
        },
        false => Box::new(std::fs::File::open(path)?),
    };
    let mut raw = BufReader::with_capacity(1 << 16, source);
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

/// Whether a file argument means standard input (or, for an output, standard output).
pub(crate) fn is_stdin(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Standard input read whole (at most [`MAX_FILE_BYTES`]), once, for readers that must look
/// at it before they parse it, or read it twice.
static STDIN: std::sync::OnceLock<Result<Vec<u8>, String>> = std::sync::OnceLock::new();

/// The first `n` bytes of standard input (reading and caching it whole), e.g. to tell a CSV
/// log from fbSAT scenarios.
pub(crate) fn stdin_text_head(n: usize) -> std::io::Result<Vec<u8>> {
    let all = STDIN.get_or_init(|| {
        let mut buf = Vec::new();
        std::io::stdin()
            .take(MAX_FILE_BYTES + 1)
            .read_to_end(&mut buf)
            .map_err(|e| e.to_string())?;
        match buf.len() as u64 > MAX_FILE_BYTES {
            true => Err(format!(
                "standard input holds more than {MAX_FILE_BYTES} bytes"
            )),
            false => Ok(buf),
        }
    });
    match all {
        Ok(bytes) => Ok(bytes[..n.min(bytes.len())].to_vec()),
        Err(e) => Err(std::io::Error::other(e.clone())),
    }
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
            // The rest of the buffer too: a reader that looks at its first `fill_buf` (the
            // delimiter sniffing of raw logs) must see a whole line, not the three bytes
            // read to look for the mark.
            if n < buf.len() {
                match self.inner.read(&mut buf[n..]) {
                    Ok(m) => return Ok(n + m),
                    // Reported by the next read, which meets it again.
                    Err(_) => return Ok(n),
                }
            }
            return Ok(n);
        }
        self.inner.read(buf)
    }
}

/// Why the text of a user's file could not be read (the file is named by [`FileReadError`]).
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// Opening or reading the file failed (missing, unreadable, a folder, ...).
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// A line holds more than `limit` bytes, its line break not counted.
    #[error("line {line} is longer than {limit} bytes")]
    LineTooLong {
        /// 1-based number of the long line.
        line: usize,
        /// The most bytes a line may hold.
        limit: usize,
    },
    /// A CSV record that quoted line breaks spread over several lines holds more than `limit`
    /// bytes: most likely a quote that is never closed.
    #[error("the record from line {first} to line {line} is longer than {limit} bytes (is a quote left open?)")]
    RecordTooLong {
        /// 1-based line the record starts on.
        first: usize,
        /// 1-based line where the record went over the limit.
        line: usize,
        /// The most bytes a record may hold.
        limit: usize,
    },
    /// A file read whole holds more than `limit` bytes (after gunzipping).
    #[error("larger than {}, the most read from one file", bytes(*limit))]
    TooLarge {
        /// The most bytes read from one file.
        limit: u64,
    },
    /// A gzip file whose stream is broken (truncated, corrupted).
    #[error("not a valid gzip stream: {message}")]
    Gzip {
        /// The decompressor's description of the fault.
        message: String,
    },
    /// A byte sequence that is not UTF-8, first on `line`.
    #[error("not UTF-8 text")]
    NotUtf8 {
        /// 1-based line of the first invalid byte.
        line: usize,
    },
}

impl ReadError {
    /// The line the problem is on, if it is on one.
    pub fn line(&self) -> Option<usize> {
        match self {
            ReadError::Io(_) | ReadError::TooLarge { .. } | ReadError::Gzip { .. } => None,
            ReadError::LineTooLong { line, .. }
            | ReadError::RecordTooLong { line, .. }
            | ReadError::NotUtf8 { line } => Some(*line),
        }
    }

    /// The error with the file it is about.
    pub(crate) fn at(self, file: &Path) -> FileReadError {
        FileReadError {
            file: file.to_path_buf(),
            error: self,
        }
    }
}

/// A [`ReadError`] in a named file: displayed `FILE:LINE: ...` when the problem is on a line,
/// `FILE: ...` otherwise.
#[derive(Debug, thiserror::Error)]
pub struct FileReadError {
    /// The file, as the user named it.
    pub file: PathBuf,
    /// What went wrong in it.
    #[source]
    pub error: ReadError,
}

impl std::fmt::Display for FileReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let file = self.file.display();
        match self.error.line() {
            Some(line) => write!(f, "{file}:{line}: {}", self.error),
            None => write!(f, "{file}: {}", self.error),
        }
    }
}

/// What [`read_line`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LineRead {
    /// The input had ended: nothing was appended.
    End,
    /// A line was appended (with its line break, unless it is the last line and has none).
    Line,
    /// The unit passed `limit`: stop reading it.
    TooLong,
}

/// Appends the next line of `src`, its line break included, to `buf`, whose bytes from `from`
/// on are the unit being read (one line, or a record that quoted line breaks spread over
/// several). [`LineRead::TooLong`] when the unit would hold more than `limit` bytes, its final
/// line break (LF or CRLF) not counted; by then at most `limit + 2` bytes of it are in `buf`,
/// however long the line in `src`.
pub(crate) fn read_line(
    src: &mut impl BufRead,
    buf: &mut Vec<u8>,
    from: usize,
    limit: usize,
) -> std::io::Result<LineRead> {
    use std::io::Read;
    // Two bytes past the limit leave room for the CRLF of a line that ends right at it.
    let room = limit.saturating_add(2).saturating_sub(buf.len() - from);
    if room == 0 {
        // The unit is full; a further line could only make it longer.
        return Ok(match src.fill_buf()?.is_empty() {
            true => LineRead::End,
            false => LineRead::TooLong,
        });
    }
    if (&mut *src).take(room as u64).read_until(b'\n', buf)? == 0 {
        return Ok(LineRead::End);
    }
    let unit = &buf[from..];
    let end = match unit {
        [.., b'\r', b'\n'] => 2,
        [.., b'\n'] => 1,
        _ => 0,
    };
    Ok(match unit.len() - end > limit {
        true => LineRead::TooLong,
        false => LineRead::Line,
    })
}

/// `1073741824 bytes (1 GiB)`: a size in bytes, and in MiB or GiB when it is a whole number of
/// them.
fn bytes(n: u64) -> String {
    match n {
        0 => "0 bytes".into(),
        _ if n.is_multiple_of(1 << 30) => format!("{n} bytes ({} GiB)", n >> 30),
        _ if n.is_multiple_of(1 << 20) => format!("{n} bytes ({} MiB)", n >> 20),
        _ => format!("{n} bytes"),
    }
}

/// Reads all of `src`, refusing more than `max_file` bytes and, with `max_line`, a line longer
/// than that (its line break not counted). Either is found having read at most a line past
/// the limit, so an endless input ends in an error, not in all of memory.
pub(crate) fn read_all(
    mut src: impl BufRead,
    max_line: Option<usize>,
    max_file: u64,
) -> Result<Vec<u8>, ReadError> {
    use std::io::Read;
    let mut all = Vec::new();
    match max_line {
        // Files whose one line may be long (an fbSAT scenario, a JSON machine).
        None => {
            // Exactly the limit, then a look for more: a Vec grown to the limit and one byte
            // would double to twice the limit.
            (&mut src).take(max_file).read_to_end(&mut all)?;
            if !src.fill_buf()?.is_empty() {
                return Err(ReadError::TooLarge { limit: max_file });
            }
        }
        Some(limit) => {
            let mut line = 0;
            loop {
                let from = all.len();
                match read_line(&mut src, &mut all, from, limit)? {
                    LineRead::End => break,
                    LineRead::Line => line += 1,
                    LineRead::TooLong => {
                        return Err(ReadError::LineTooLong {
                            line: line + 1,
                            limit,
                        })
                    }
                }
                if all.len() as u64 > max_file {
                    return Err(ReadError::TooLarge { limit: max_file });
                }
            }
        }
    }
    Ok(all)
}

/// The bytes as text, or the line of the first byte that is not UTF-8.
pub(crate) fn utf8_text(bytes: Vec<u8>) -> Result<String, ReadError> {
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..valid]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        ReadError::NotUtf8 { line }
    })
}

/// Reads a user's text file whole through [`open_input`] (gunzipped when it is gzip, without a
/// leading byte order mark), with the limits of [`read_all`]: at most [`MAX_FILE_BYTES`] of
/// text, and lines of at most `max_line` bytes when given. A plain file over the size limit is
/// refused before it is read.
pub fn read_text(path: &Path, max_line: Option<usize>) -> Result<String, FileReadError> {
    let read = || -> Result<String, ReadError> {
        let input = open_input(path)?;
        if !input.gzip && !is_stdin(path) {
            let meta = std::fs::metadata(path)?;
            if meta.is_file() && meta.len() > MAX_FILE_BYTES {
                return Err(ReadError::TooLarge {
                    limit: MAX_FILE_BYTES,
                });
            }
        }
        let all = read_all(input.reader, max_line, MAX_FILE_BYTES).map_err(|e| match e {
            ReadError::Io(e) if input.gzip => ReadError::Gzip {
                message: e.to_string(),
            },
            e => e,
        })?;
        utf8_text(all)
    };
    read().map_err(|e| e.at(path))
}

/// A file that could not be written, with its path.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {source}")]
pub struct WriteError {
    /// The file that was being written.
    pub path: PathBuf,
    /// The I/O failure: creating a folder or the temporary file, writing, or renaming it.
    #[source]
    pub(crate) source: std::io::Error,
}

/// What a writer does about missing folders above the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Folders {
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
pub(crate) fn write_atomic_in(
    path: &Path,
    bytes: &[u8],
    folders: Folders,
) -> Result<(), WriteError> {
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
pub(crate) struct AtomicFile {
    path: PathBuf,
    /// Where the temporary file is renamed to: `path` with its symbolic links followed.
    target: PathBuf,
    out: Sink,
    /// Removes the temporary file on a termination signal until it is renamed or dropped.
    _on_signal: Option<RemovedOnSignal>,
}

/// [`remove_on_signal`] for as long as this lives.
struct RemovedOnSignal(PathBuf);

impl Drop for RemovedOnSignal {
    fn drop(&mut self) {
        keep_on_signal(&self.0);
    }
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
    pub(crate) fn create(path: &Path) -> Result<AtomicFile, WriteError> {
        AtomicFile::open(path, Folders::Create)
    }

    /// Starts writing `path`, creating missing parent folders or not as `folders` says
    /// (`.gz` paths are gzip-compressed).
    pub(crate) fn open(path: &Path, folders: Folders) -> Result<AtomicFile, WriteError> {
        let err = |source| WriteError {
            path: path.to_path_buf(),
            source,
        };
        let target = follow_links(path);
        // Asked of `path` itself: the kernel follows links that no path spells out, as
        // `/dev/stdout` -> `/proc/self/fd/1` -> `pipe:[...]` on a pipe.
        let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir());
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if folders == Folders::Create && !special {
            std::fs::create_dir_all(dir).map_err(err)?;
        }
        let mut on_signal = None;
        let file = if special {
            Target::Special(
                std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(err)?,
            )
        } else {
            let tmp = temporary_in(dir).map_err(err)?;
            // A long stream (ingest, events) may be interrupted: no hidden `.tmp*` stays.
            remove_on_signal(tmp.path());
            on_signal = Some(RemovedOnSignal(tmp.path().to_path_buf()));
            Target::Temporary(tmp)
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
            _on_signal: on_signal,
        })
    }

    /// The error for `source`, naming this file.
    pub(crate) fn error(&self, source: std::io::Error) -> WriteError {
        WriteError {
            path: self.path.clone(),
            source,
        }
    }

    /// Flushes, syncs and renames the temporary file over the target path (a special file:
    /// flushes what was written into it).
    pub(crate) fn commit(self) -> Result<(), WriteError> {
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
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
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
    fn read_all_stops_just_past_its_limits() {
        use std::io::repeat;
        // An endless input: only the limits end the reading.
        let endless = || BufReader::new(repeat(b'0'));
        let e = read_all(endless(), None, 1000).unwrap_err();
        assert!(matches!(e, ReadError::TooLarge { limit: 1000 }), "{e}");
        assert_eq!(
            e.to_string(),
            "larger than 1000 bytes, the most read from one file"
        );
        let e = read_all(endless(), Some(10), 1000).unwrap_err();
        assert!(
            matches!(e, ReadError::LineTooLong { line: 1, limit: 10 }),
            "{e}"
        );
        let lines = || BufReader::new(repeat(b'\n'));
        let e = read_all(lines(), Some(10), 1000).unwrap_err();
        assert!(matches!(e, ReadError::TooLarge { limit: 1000 }), "{e}");
        let e = read_all(&b"short\r\nten bytes.\r\n11 bytes...\n"[..], Some(10), 1000);
        assert!(
            matches!(e, Err(ReadError::LineTooLong { line: 3, limit: 10 })),
            "{e:?}"
        );
        // Exactly at both limits is still read.
        let text = b"ten bytes.\nten bytes.";
        assert_eq!(read_all(&text[..], Some(10), 21).unwrap(), text);
        assert_eq!(read_all(&text[..], None, 21).unwrap(), text);
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
        assert_eq!(read_text(&packed, None).unwrap(), "in:a\n");
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
        let e = read_text(&path, None).unwrap_err();
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
