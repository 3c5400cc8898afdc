//! Writing files so that a failure never leaves a half-written one behind.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file that could not be written, with its path.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {source}")]
pub struct WriteError {
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

/// Writes `bytes` to `path` atomically: into a temporary file in the same folder, then renamed
/// over `path`. Creates missing parent folders. Paths ending in `.gz` are gzip-compressed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes).map_err(|e| file.error(e))?;
    file.commit()
}

/// A file written as a stream and published atomically, like [`write_atomic`]: the content
/// goes into a temporary file beside `path`, which [`AtomicFile::commit`] renames over `path`.
/// Dropped without a commit, the temporary file is removed and `path` is left as it was.
pub struct AtomicFile {
    path: PathBuf,
    out: Sink,
}

enum Sink {
    Plain(BufWriter<tempfile::NamedTempFile>),
    Gzip(flate2::write::GzEncoder<BufWriter<tempfile::NamedTempFile>>),
}

impl AtomicFile {
    /// Starts writing `path` (parent folders are created; `.gz` paths are gzip-compressed).
    pub fn create(path: &Path) -> Result<AtomicFile, WriteError> {
        let err = |source| WriteError {
            path: path.to_path_buf(),
            source,
        };
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::create_dir_all(dir).map_err(err)?;
        let tmp =
            BufWriter::with_capacity(1 << 16, tempfile::NamedTempFile::new_in(dir).map_err(err)?);
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

    /// Flushes, syncs and renames the temporary file over the target path.
    pub fn commit(self) -> Result<(), WriteError> {
        let path = self.path;
        let err = |source| WriteError {
            path: path.clone(),
            source,
        };
        let buffered = match self.out {
            Sink::Plain(b) => b,
            Sink::Gzip(gz) => gz.finish().map_err(err)?,
        };
        let tmp = buffered.into_inner().map_err(|e| err(e.into_error()))?;
        tmp.as_file().sync_all().map_err(err)?;
        // Temporary files are created private (0600); results are ordinary files.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644))
                .map_err(err)?;
        }
        tmp.persist(&path).map_err(|e| err(e.error))?;
        Ok(())
    }
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
