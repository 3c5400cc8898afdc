//! A result set: the files one run writes into its output folder, published together.
//!
//! A run takes its output folder when it starts ([`ResultSet::open`]): it creates it, locks
//! it (`.synth.lock`, an advisory `flock`, so a second run into the same folder stops at once
//! instead of mixing its files with the first run's), and makes a staging folder inside it
//! (`.synth-staging-*`). Writers write into [`ResultSet::staging`]; nothing appears in the
//! output folder until [`ResultSet::publish`] moves every staged file into place, one rename
//! each (all on the same file system, after every file was written in full). Files that the
//! previous run published there (listed in `.synth-files`) and this one did not write are
//! removed, so the folder never holds files of two different results. A run that fails, or
//! is interrupted by a signal, leaves the folder as it was.

use super::{write_atomic, WriteError};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The lock file inside an output folder.
pub(crate) const LOCK: &str = ".synth.lock";
/// The list of files the last run published into an output folder.
pub(crate) const MANIFEST: &str = ".synth-files";

/// An output folder taken by this run.
pub(crate) struct ResultSet {
    out: PathBuf,
    /// This run made the folder: a run that publishes nothing removes it again.
    created: bool,
    /// This run made the lock file: a run that publishes nothing removes it again.
    lock_created: bool,
    published: bool,
    staging: tempfile::TempDir,
    // Held for the whole run, released in `drop`.
    lock: std::fs::File,
}

/// Why an output folder cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ResultSetError {
    /// Another run holds the folder's lock.
    #[error("another synth run is writing into {} (it holds {}); wait for it to finish or give another output folder", .out.display(), .out.join(LOCK).display())]
    Busy {
        /// The output folder.
        out: PathBuf,
    },
    /// The folder or its staging area cannot be made.
    #[error(transparent)]
    Write(#[from] WriteError),
}

impl ResultSet {
    /// Creates `out` if needed, locks it for this run and makes the staging folder.
    pub(crate) fn open(out: &Path) -> Result<ResultSet, ResultSetError> {
        let err = |path: &Path| {
            let path = path.to_path_buf();
            move |source| WriteError { path, source }
        };
        if out.exists() && !out.is_dir() {
            return Err(ResultSetError::Write(WriteError {
                path: out.to_path_buf(),
                source: std::io::Error::other(
                    "it is a file, not a folder: give a folder for the results",
                ),
            }));
        }
        let created = !out.exists();
        std::fs::create_dir_all(out).map_err(err(out))?;
        if created {
            super::remove_empty_on_signal(out);
        }
        let lock_path = out.join(LOCK);
        let lock_created = !lock_path.exists();
        let lock = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(err(&lock_path))?;
        lock_exclusively(&lock, out)?;
        if lock_created {
            super::remove_on_signal(&lock_path);
        }
        let staging = tempfile::Builder::new()
            .prefix(".synth-staging-")
            .tempdir_in(out)
            .map_err(err(out))?;
        super::remove_on_signal(staging.path());
        Ok(ResultSet {
            out: out.to_path_buf(),
            created,
            lock_created,
            published: false,
            staging,
            lock,
        })
    }

    /// The folder to write the results into.
    pub(crate) fn staging(&self) -> &Path {
        self.staging.path()
    }

    /// Where a file written at `staged` (inside [`Self::staging`]) is after publishing.
    pub(crate) fn published(&self, staged: &Path) -> PathBuf {
        match staged.strip_prefix(self.staging.path()) {
            Ok(rel) => self.out.join(rel),
            Err(_) => staged.to_path_buf(),
        }
    }

    /// Moves every staged file into the output folder, removes what the previous run
    /// published and this one did not, and records the new list. Returns the files published
    /// (relative to the output folder, sorted).
    pub(crate) fn publish(mut self) -> Result<Vec<PathBuf>, WriteError> {
        self.published = true;
        let mut files = Vec::new();
        walk(self.staging.path(), Path::new(""), &mut files).map_err(|source| WriteError {
            path: self.staging.path().to_path_buf(),
            source,
        })?;
        files.sort();
        // A folder where a file goes (or a file where a folder goes) would stop the moves
        // half-way: found before the first one.
        for rel in &files {
            let to = self.out.join(rel);
            let leaf = std::fs::symlink_metadata(&to).is_ok_and(|m| m.is_dir());
            let clash = if leaf {
                Some((to.clone(), "a folder"))
            } else {
                // A parent that exists as something else than a folder (links followed).
                to.ancestors()
                    .skip(1)
                    .take_while(|a| *a != self.out)
                    .find(|a| a.exists() && !a.is_dir())
                    .map(|a| (a.to_path_buf(), "a file"))
            };
            if let Some((at, what)) = clash {
                return Err(WriteError {
                    path: to,
                    source: std::io::Error::other(format!(
                        "{} is {what}; move it away or give another output folder",
                        at.display()
                    )),
                });
            }
        }
        // The files replaced are kept aside in the staging folder until every new one is in
        // place, and put back if a move still fails: the folder holds one result or the other.
        let previous = self.staging.path().join(".previous");
        let mut moved: Vec<(PathBuf, Option<PathBuf>)> = Vec::new();
        for rel in &files {
            let to = self.out.join(rel);
            match self.move_in(rel, &to, &previous.join(rel)) {
                Ok(saved) => moved.push((to, saved)),
                Err(source) => {
                    for (to, saved) in moved.into_iter().rev() {
                        let _ = std::fs::remove_file(&to);
                        if let Some(saved) = saved {
                            let _ = std::fs::rename(saved, &to);
                        }
                    }
                    return Err(WriteError { path: to, source });
                }
            }
        }
        let manifest = self.out.join(MANIFEST);
        let now: BTreeSet<&PathBuf> = files.iter().collect();
        if let Ok(before) = std::fs::read_to_string(&manifest) {
            for line in before.lines() {
                let rel = PathBuf::from(line);
                // Only plain relative names inside the folder: the manifest is ours, but it is
                // a file in a user's folder.
                let inside = rel
                    .components()
                    .all(|c| matches!(c, std::path::Component::Normal(_)));
                if inside && !now.contains(&rel) {
                    let old = self.out.join(&rel);
                    if std::fs::symlink_metadata(&old).is_ok_and(|m| m.is_file()) {
                        let _ = std::fs::remove_file(&old);
                    }
                }
            }
        }
        let list: String = files.iter().map(|f| format!("{}\n", f.display())).collect();
        write_atomic(&manifest, list.as_bytes())?;
        Ok(files)
    }

    /// Moves the staged file `rel` to `to`, first moving a file already there to `saved`
    /// (returned when it did).
    fn move_in(&self, rel: &Path, to: &Path, saved: &Path) -> std::io::Result<Option<PathBuf>> {
        if let Some(dir) = to.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let kept = if std::fs::symlink_metadata(to).is_ok() {
            if let Some(dir) = saved.parent() {
                std::fs::create_dir_all(dir)?;
            }
            std::fs::rename(to, saved)?;
            Some(saved.to_path_buf())
        } else {
            None
        };
        if let Err(e) = std::fs::rename(self.staging.path().join(rel), to) {
            if let Some(saved) = &kept {
                let _ = std::fs::rename(saved, to);
            }
            return Err(e);
        }
        Ok(kept)
    }
}

impl Drop for ResultSet {
    fn drop(&mut self) {
        self.leave();
        // Last, once the lock file is gone if this run made it: released before that, another
        // run could lock the file this one is about to remove.
        unlock(&self.lock);
    }
}

impl ResultSet {
    fn leave(&mut self) {
        // The staging folder goes with its TempDir right after this.
        super::keep_on_signal(self.staging.path());
        super::keep_on_signal(&self.out.join(LOCK));
        super::keep_on_signal(&self.out);
        if self.published {
            return;
        }
        // A failed run leaves nothing: no lock file it made, no folder it made
        // (remove_dir fails, as it should, if anything else is in it).
        if self.lock_created {
            let _ = std::fs::remove_file(self.out.join(LOCK));
        }
        if self.created {
            let _ = std::fs::remove_dir_all(self.staging.path());
            let _ = std::fs::remove_dir(&self.out);
        }
    }
}

fn walk(dir: &Path, rel: &Path, files: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let rel = rel.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            walk(&entry.path(), &rel, files)?;
        } else {
            files.push(rel);
        }
    }
    Ok(())
}

#[cfg(unix)]
fn lock_exclusively(file: &std::fs::File, out: &Path) -> Result<(), ResultSetError> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a file descriptor this function borrows for the call.
    let r = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if r == 0 {
        return Ok(());
    }
    let e = std::io::Error::last_os_error();
    match e.raw_os_error() {
        Some(libc::EWOULDBLOCK) => Err(ResultSetError::Busy {
            out: out.to_path_buf(),
        }),
        _ => Err(ResultSetError::Write(WriteError {
            path: out.join(LOCK),
            source: e,
        })),
    }
}

/// Releases the folder's lock now. Closing the file is not enough: a child process that
/// another thread is starting may hold a copy of the descriptor until its `exec`, and the
/// lock belongs to the open file, so it would outlive this run for that moment.
#[cfg(unix)]
fn unlock(file: &std::fs::File) {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a file descriptor this function borrows for the call.
    unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_UN) };
}

#[cfg(not(unix))]
fn unlock(_: &std::fs::File) {}

#[cfg(not(unix))]
fn lock_exclusively(_: &std::fs::File, _: &Path) -> Result<(), ResultSetError> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_appears_before_publish_and_stale_files_go() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let set = ResultSet::open(&out).unwrap();
        write_atomic(&set.staging().join("a.json"), b"1").unwrap();
        write_atomic(&set.staging().join("b.fbt"), b"2").unwrap();
        assert!(!out.join("a.json").exists());
        assert_eq!(
            set.published(&set.staging().join("a.json")),
            out.join("a.json")
        );
        let files = set.publish().unwrap();
        assert_eq!(files, [PathBuf::from("a.json"), PathBuf::from("b.fbt")]);
        assert_eq!(std::fs::read(out.join("b.fbt")).unwrap(), b"2");
        // A user's own file stays; the previous run's b.fbt goes with a run that lacks it.
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        let set = ResultSet::open(&out).unwrap();
        write_atomic(&set.staging().join("a.json"), b"3").unwrap();
        set.publish().unwrap();
        assert_eq!(std::fs::read(out.join("a.json")).unwrap(), b"3");
        assert!(!out.join("b.fbt").exists());
        assert!(out.join("notes.txt").exists());
        let left: Vec<_> = std::fs::read_dir(&out)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(".synth-staging"))
            .collect();
        assert!(left.is_empty(), "{left:?}");
    }

    #[test]
    fn a_publish_that_cannot_place_every_file_changes_none() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.json"), "old").unwrap();
        std::fs::create_dir(dir.path().join("b.st")).unwrap();
        let set = ResultSet::open(dir.path()).unwrap();
        write_atomic(&set.staging().join("a.json"), b"new").unwrap();
        write_atomic(&set.staging().join("b.st"), b"new").unwrap();
        let e = set.publish().unwrap_err();
        assert!(e.to_string().contains("is a folder"), "{e}");
        assert_eq!(
            std::fs::read_to_string(dir.path().join("a.json")).unwrap(),
            "old"
        );
        assert!(dir.path().join("b.st").is_dir());
    }

    #[test]
    fn a_failed_run_removes_the_folder_it_made() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("new");
        let set = ResultSet::open(&out).unwrap();
        write_atomic(&set.staging().join("a.json"), b"1").unwrap();
        drop(set);
        assert!(!out.exists());
    }

    #[test]
    fn a_second_run_into_a_taken_folder_stops() {
        let dir = tempfile::tempdir().unwrap();
        let first = ResultSet::open(dir.path()).unwrap();
        let second = ResultSet::open(dir.path());
        assert!(
            matches!(second, Err(ResultSetError::Busy { .. })),
            "the folder is taken"
        );
        drop(first);
        assert!(ResultSet::open(dir.path()).is_ok());
    }

    #[test]
    #[cfg(unix)]
    fn a_finished_run_frees_the_folder_while_other_threads_start_processes() {
        // A process started from another thread holds copies of this run's descriptors
        // until it execs; the folder must be free again the moment the run ends.
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let spawner = {
            let stop = stop.clone();
            std::thread::spawn(move || {
                use std::os::unix::process::CommandExt;
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    let mut command = std::process::Command::new("true");
                    // SAFETY: usleep is async-signal-safe; the pause widens the window
                    // between fork and exec, as the NuSMV driver's own pre_exec does.
                    unsafe {
                        command.pre_exec(|| {
                            libc::usleep(2000);
                            Ok(())
                        });
                    }
                    let _ = command.status();
                }
            })
        };
        let dir = tempfile::tempdir().unwrap();
        let busy = (0..100)
            .filter(|_| {
                let first = ResultSet::open(dir.path()).unwrap();
                std::thread::sleep(std::time::Duration::from_millis(1));
                // Published, so the lock file stays for the next run.
                first.publish().unwrap();
                ResultSet::open(dir.path()).is_err()
            })
            .count();
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        spawner.join().unwrap();
        assert_eq!(
            busy, 0,
            "runs found the folder taken after the previous run ended"
        );
    }

    #[test]
    fn a_dropped_set_leaves_the_folder_as_it_was() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.json"), "old").unwrap();
        let set = ResultSet::open(dir.path()).unwrap();
        write_atomic(&set.staging().join("a.json"), b"new").unwrap();
        drop(set);
        assert_eq!(
            std::fs::read_to_string(dir.path().join("a.json")).unwrap(),
            "old"
        );
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert!(
            names.iter().all(|n| !n.starts_with(".synth-staging")),
            "{names:?}"
        );
    }
}
