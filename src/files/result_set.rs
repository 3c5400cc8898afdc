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
//! is interrupted by a signal, leaves the folder as it was; what a run killed outright left
//! (its staging folder) goes when the next run takes the folder. The output rule
//! ([`super::output_rule`]) is checked when the folder is taken and again when publishing.

use super::output_rule::{Claim, RuleError};
use super::{write_atomic, WriteError};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The lock file inside an output folder.
pub(crate) const LOCK: &str = ".synth.lock";
/// The list of files the last run published into an output folder, after a first line that
/// names its command ([`HEADER`]).
pub(crate) const MANIFEST: &str = ".synth-files";
/// How the list of files names the command that wrote it: `#command infer`.
const HEADER: &str = "#command ";
/// The prefix of staging folders.
const STAGING: &str = ".synth-staging-";

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
    claim: Claim,
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
    /// The output rule refuses the folder.
    #[error(transparent)]
    Rule(#[from] RuleError),
}

impl ResultSet {
    /// Creates `out` if needed, locks it for this run and makes the staging folder, once the
    /// output rule allows the run its `claim`.
    pub(crate) fn open(out: &Path, claim: Claim) -> Result<ResultSet, ResultSetError> {
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
        let (previous, listed) = read_manifest(out);
        claim.check_folder(out, previous.as_deref(), &listed)?;
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
        remove_dead_staging(out);
        let staging = tempfile::Builder::new()
            .prefix(STAGING)
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
            claim,
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
    pub(crate) fn publish(mut self) -> Result<Vec<PathBuf>, ResultSetError> {
        // A signal waits for the moves: the folder holds one result or the other.
        let hold = crate::signals::hold();
        let files = self.publish_held()?;
        self.published = true;
        hold.published();
        Ok(files)
    }

    fn publish_held(&mut self) -> Result<Vec<PathBuf>, ResultSetError> {
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
                return Err(ResultSetError::Write(WriteError {
                    path: to,
                    source: std::io::Error::other(format!(
                        "{} is {what}; move it away or give another output folder",
                        at.display()
                    )),
                }));
            }
        }
        let (_, listed) = read_manifest(&self.out);
        let gone = listed.iter().filter(|rel| !files.contains(rel));
        for rel in files.iter().chain(gone) {
            self.claim.check_target(&self.out.join(rel))?;
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
                    return Err(WriteError { path: to, source }.into());
                }
            }
        }
        let now: BTreeSet<&PathBuf> = files.iter().collect();
        for rel in listed.iter().filter(|rel| !now.contains(rel)) {
            let old = self.out.join(rel);
            if std::fs::symlink_metadata(&old).is_ok_and(|m| m.is_file()) {
                let _ = std::fs::remove_file(&old);
            }
        }
        let list: String = files.iter().map(|f| format!("{}\n", f.display())).collect();
        let text = format!("{HEADER}{}\n{list}", self.claim.command);
        write_atomic(&self.out.join(MANIFEST), text.as_bytes())?;
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
        // Gone while the lock is still held: the next run takes any staging folder it finds
        // for a dead run's.
        let _ = std::fs::remove_dir_all(self.staging.path());
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

/// The command that wrote the folder's list of files (none before lists named it), and the
/// files listed: plain relative names only (the list is ours, but it is a file in a user's
/// folder).
fn read_manifest(out: &Path) -> (Option<String>, Vec<PathBuf>) {
    let Ok(text) = std::fs::read_to_string(out.join(MANIFEST)) else {
        return (None, Vec::new());
    };
    let mut command = None;
    let mut files = Vec::new();
    for line in text.lines() {
        if let Some(c) = line.strip_prefix(HEADER) {
            command = Some(c.to_string());
            continue;
        }
        let rel = PathBuf::from(line);
        let plain = (rel.components()).all(|c| matches!(c, std::path::Component::Normal(_)));
        if plain && !line.is_empty() {
            files.push(rel);
        }
    }
    (command, files)
}

/// Removes the staging folders of runs that died in the folder (killed outright): the caller
/// holds the lock, so no live run stages there.
fn remove_dead_staging(out: &Path) {
    let Ok(entries) = std::fs::read_dir(out) else {
        return;
    };
    for e in entries.flatten() {
        let dir = e.file_type().is_ok_and(|t| t.is_dir());
        if dir && e.file_name().to_string_lossy().starts_with(STAGING) {
            let _ = std::fs::remove_dir_all(e.path());
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
        let set = ResultSet::open(&out, Claim::default()).unwrap();
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
        let set = ResultSet::open(&out, Claim::default()).unwrap();
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
        let set = ResultSet::open(dir.path(), Claim::default()).unwrap();
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
        let set = ResultSet::open(&out, Claim::default()).unwrap();
        write_atomic(&set.staging().join("a.json"), b"1").unwrap();
        drop(set);
        assert!(!out.exists());
    }

    #[test]
    fn a_second_run_into_a_taken_folder_stops() {
        let dir = tempfile::tempdir().unwrap();
        let first = ResultSet::open(dir.path(), Claim::default()).unwrap();
        let second = ResultSet::open(dir.path(), Claim::default());
        assert!(
            matches!(second, Err(ResultSetError::Busy { .. })),
            "the folder is taken"
        );
        drop(first);
        assert!(ResultSet::open(dir.path(), Claim::default()).is_ok());
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
                let first = ResultSet::open(dir.path(), Claim::default()).unwrap();
                std::thread::sleep(std::time::Duration::from_millis(1));
                // Published, so the lock file stays for the next run.
                first.publish().unwrap();
                ResultSet::open(dir.path(), Claim::default()).is_err()
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
        let set = ResultSet::open(dir.path(), Claim::default()).unwrap();
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

    #[test]
    fn a_dead_runs_staging_folder_goes_with_the_next_run() {
        let dir = tempfile::tempdir().unwrap();
        let dead = dir.path().join(".synth-staging-dead");
        std::fs::create_dir(&dead).unwrap();
        std::fs::write(dead.join("a.json"), "half").unwrap();
        let set = ResultSet::open(dir.path(), Claim::default()).unwrap();
        assert!(!dead.exists());
        drop(set);
    }

    #[test]
    fn inputs_and_other_commands_results_are_never_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let set = ResultSet::open(&out, Claim::new("infer", [] as [&Path; 0])).unwrap();
        write_atomic(&set.staging().join("m.json"), b"1").unwrap();
        write_atomic(&set.staging().join("data.txt"), b"1").unwrap();
        set.publish().unwrap();
        let manifest = std::fs::read_to_string(out.join(MANIFEST)).unwrap();
        assert!(manifest.starts_with("#command infer\n"), "{manifest}");
        // Another command: refused before anything is made.
        let e = ResultSet::open(&out, Claim::new("verify", [] as [&Path; 0])).err();
        assert!(
            matches!(e, Some(ResultSetError::Rule(RuleError::Other { .. }))),
            "{e:?}"
        );
        // An input the previous result listed (publishing would remove it).
        let input = out.join("m.json");
        let e = ResultSet::open(&out, Claim::new("infer", [&input])).err();
        assert!(
            matches!(e, Some(ResultSetError::Rule(RuleError::Input { .. }))),
            "{e:?}"
        );
        // An input under a name no rule knows in advance, found when publishing over it (a
        // hard link is the same file): nothing moves.
        let linked = dir.path().join("linked.txt");
        std::fs::hard_link(out.join("data.txt"), &linked).unwrap();
        std::fs::write(out.join("data.txt"), "mine").unwrap();
        std::fs::remove_file(out.join(MANIFEST)).unwrap();
        let set = ResultSet::open(&out, Claim::new("infer", [&linked])).unwrap();
        write_atomic(&set.staging().join("data.txt"), b"2").unwrap();
        let e = set.publish().unwrap_err();
        assert!(e.to_string().contains("linked.txt"), "{e}");
        assert_eq!(std::fs::read_to_string(&linked).unwrap(), "mine");
    }

    /// Run in a child test process by `a_signal_while_publishing_waits_for_the_result`:
    /// publishes many files and sends itself SIGTERM once the publish holds signals; exits
    /// with 7, the run's own outcome, if the signal did not end it. Does nothing in a normal
    /// test run.
    #[test]
    fn publish_signal_helper() {
        let Some(out) = std::env::var_os(SIGNAL_HELPER) else {
            return;
        };
        let out = PathBuf::from(out);
        let set = ResultSet::open(&out, Claim::default()).unwrap();
        // Plain writes (no sync each): the test is about the moves.
        for k in 0..5000 {
            std::fs::write(set.staging().join(format!("f{k}.txt")), b"x").unwrap();
        }
        let signaller = std::thread::spawn(|| {
            while !crate::signals::held() {
                std::hint::spin_loop();
            }
            // SAFETY: a signal to this very process.
            unsafe { libc::kill(libc::getpid(), libc::SIGTERM) };
        });
        set.publish().unwrap();
        signaller.join().unwrap();
        std::process::exit(7);
    }

    const SIGNAL_HELPER: &str = "FBSYNTH_PUBLISH_SIGNAL_HELPER";

    #[test]
    #[cfg(target_os = "linux")]
    fn a_signal_while_publishing_waits_for_the_result() {
        let dir = tempfile::tempdir().unwrap();
        let status = std::process::Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "files::result_set::tests::publish_signal_helper",
                "--test-threads",
                "1",
            ])
            .env(SIGNAL_HELPER, dir.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .unwrap();
        assert_eq!(status.code(), Some(7));
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert!(
            names.iter().all(|n| !n.starts_with(STAGING)),
            "staging left"
        );
        assert_eq!(names.iter().filter(|n| n.ends_with(".txt")).count(), 5000);
    }
}
