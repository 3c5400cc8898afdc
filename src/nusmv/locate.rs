//! Finding the NuSMV binary.
//!
//! In: the `--nusmv PATH` option if given, and the environment. Out: the path of a NuSMV
//! binary, looked up in this order:
//! 1. `--nusmv PATH` (a bare name without `/` is also looked up in `PATH`);
//! 2. `$NUSMV`, treated the same way;
//! 3. `NuSMV`, then `nusmv`, in `PATH`;
//! 4. the folder `.ci/install-nusmv.sh` installs into:
//!    `${FBSYNTH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/fbsynth}/nusmv-2.5.4/bin/NuSMV`.
//!
//! A path the user named (1 or 2) that does not exist is an error of its own rather than a
//! reason to fall back: running some other NuSMV than the one asked for would be a surprise.

use super::NusmvError;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// How to get NuSMV, in one line (the message of [`NusmvError::NotFound`]).
pub(crate) const INSTALL_HINT: &str = "run .ci/install-nusmv.sh, or pass --nusmv PATH / set NUSMV";

/// Where `.ci/install-nusmv.sh` puts the binary, relative to fbsynth's cache folder ([`Env::cache_dir`]).
pub(crate) const CACHED_BINARY: &str = "nusmv-2.5.4/bin/NuSMV";

/// Binary names tried in `PATH`, in order.
const NAMES: [&str; 2] = ["NuSMV", "nusmv"];

/// Finds NuSMV; see the module documentation for the order.
pub fn locate(explicit: Option<&Path>) -> Result<PathBuf, NusmvError> {
    locate_in(explicit, &Env::from_process())
}

/// The parts of the environment the lookup reads, apart so tests need not mutate the
/// process environment.
#[derive(Debug, Default, Clone)]
struct Env {
    nusmv: Option<OsString>,
    path: Option<OsString>,
    fbsynth_cache: Option<OsString>,
    xdg_cache_home: Option<OsString>,
    home: Option<OsString>,
    cwd: PathBuf,
}

impl Env {
    fn from_process() -> Env {
        let var = |name| std::env::var_os(name).filter(|v| !v.is_empty());
        Env {
            nusmv: var("NUSMV"),
            path: var("PATH"),
            fbsynth_cache: var("FBSYNTH_CACHE"),
            xdg_cache_home: var("XDG_CACHE_HOME"),
            home: var("HOME"),
            cwd: std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
        }
    }

    /// fbsynth's cache folder: `$FBSYNTH_CACHE`, else `$XDG_CACHE_HOME/fbsynth`, else
    /// `$HOME/.cache/fbsynth` (empty variables count as unset, as in the install script).
    fn cache_dir(&self) -> Option<PathBuf> {
        if let Some(dir) = &self.fbsynth_cache {
            return Some(PathBuf::from(dir));
        }
        if let Some(dir) = &self.xdg_cache_home {
            return Some(Path::new(dir).join("fbsynth"));
        }
        self.home
            .as_ref()
            .map(|home| Path::new(home).join(".cache").join("fbsynth"))
    }

    /// `name` looked up in `PATH` the way a shell would.
    fn which(&self, name: impl AsRef<std::ffi::OsStr>) -> Option<PathBuf> {
        which::which_in(name, self.path.as_ref(), &self.cwd).ok()
    }
}

fn locate_in(explicit: Option<&Path>, env: &Env) -> Result<PathBuf, NusmvError> {
    if let Some(path) = explicit {
        return named(path, env);
    }
    if let Some(path) = &env.nusmv {
        return named(Path::new(path), env);
    }
    if let Some(found) = NAMES.iter().find_map(|name| env.which(name)) {
        return Ok(found);
    }
    if let Some(cached) = env.cache_dir().map(|dir| dir.join(CACHED_BINARY)) {
        if cached.is_file() {
            return Ok(cached);
        }
    }
    Err(NusmvError::NotFound {
        hint: INSTALL_HINT.to_string(),
    })
}

/// A path the user gave: used as it is when it names a file, looked up in `PATH` when it is
/// a bare command name.
fn named(path: &Path, env: &Env) -> Result<PathBuf, NusmvError> {
    if path.is_file() {
        return Ok(path.to_path_buf());
    }
    let bare = path.components().count() == 1 && path.parent() == Some(Path::new(""));
    match bare.then(|| env.which(path)).flatten() {
        Some(found) => Ok(found),
        None => Err(NusmvError::ExplicitPathMissing(path.to_path_buf())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    /// A folder with fake executables `bin/NuSMV`, `other/nusmv` and a cached binary.
    struct Fakes {
        dir: tempfile::TempDir,
    }

    impl Fakes {
        fn new() -> Fakes {
            let dir = tempfile::tempdir().unwrap();
            for rel in ["bin/NuSMV", "other/nusmv", "cache/nusmv-2.5.4/bin/NuSMV"] {
                let path = dir.path().join(rel);
                fs::create_dir_all(path.parent().unwrap()).unwrap();
                fs::write(&path, "#!/bin/sh\n").unwrap();
                make_executable(&path);
            }
            Fakes { dir }
        }

        fn path(&self, rel: &str) -> PathBuf {
            self.dir.path().join(rel)
        }

        fn env(&self) -> Env {
            Env {
                cwd: self.dir.path().to_path_buf(),
                ..Env::default()
            }
        }
    }

    #[cfg(unix)]
    fn make_executable(path: &Path) {
        use std::os::unix::fs::PermissionsExt;
        fs::set_permissions(path, fs::Permissions::from_mode(0o755)).unwrap();
    }

    #[cfg(not(unix))]
    fn make_executable(_path: &Path) {}

    #[test]
    fn explicit_path_wins_over_everything() {
        let f = Fakes::new();
        let env = Env {
            nusmv: Some(f.path("other/nusmv").into()),
            path: Some(f.path("bin").into()),
            ..f.env()
        };
        let explicit = f.path("cache/nusmv-2.5.4/bin/NuSMV");
        assert_eq!(locate_in(Some(&explicit), &env).unwrap(), explicit);
    }

    #[test]
    fn missing_explicit_path_is_named_in_the_error() {
        let f = Fakes::new();
        let env = Env {
            path: Some(f.path("bin").into()),
            ..f.env()
        };
        let missing = f.path("nowhere/NuSMV");
        let err = locate_in(Some(&missing), &env).unwrap_err();
        assert!(matches!(&err, NusmvError::ExplicitPathMissing(p) if *p == missing));
        assert!(err.to_string().contains("nowhere/NuSMV"), "{err}");
    }

    #[test]
    fn a_bare_explicit_name_is_looked_up_in_path() {
        let f = Fakes::new();
        let env = Env {
            path: Some(f.path("other").into()),
            ..f.env()
        };
        let found = locate_in(Some(Path::new("nusmv")), &env).unwrap();
        assert_eq!(found, f.path("other/nusmv"));
    }

    #[test]
    fn env_var_comes_before_path_and_is_explicit_too() {
        let f = Fakes::new();
        let env = Env {
            nusmv: Some(f.path("other/nusmv").into()),
            path: Some(f.path("bin").into()),
            ..f.env()
        };
        assert_eq!(locate_in(None, &env).unwrap(), f.path("other/nusmv"));
        let env = Env {
            nusmv: Some(f.path("gone").into()),
            ..env
        };
        assert!(matches!(
            locate_in(None, &env),
            Err(NusmvError::ExplicitPathMissing(_))
        ));
    }

    #[test]
    fn path_lookup_tries_both_names() {
        let f = Fakes::new();
        let both = std::env::join_paths([f.path("other"), f.path("bin")]).unwrap();
        let env = Env {
            path: Some(both),
            ..f.env()
        };
        // `NuSMV` is tried first in the whole PATH, even though `nusmv` comes earlier.
        assert_eq!(locate_in(None, &env).unwrap(), f.path("bin/NuSMV"));
        let env = Env {
            path: Some(f.path("other").into()),
            ..f.env()
        };
        assert_eq!(locate_in(None, &env).unwrap(), f.path("other/nusmv"));
    }

    #[test]
    fn cache_folder_is_the_last_resort() {
        let f = Fakes::new();
        let env = Env {
            fbsynth_cache: Some(f.path("cache").into()),
            ..f.env()
        };
        assert_eq!(
            locate_in(None, &env).unwrap(),
            f.path("cache/nusmv-2.5.4/bin/NuSMV")
        );
    }

    #[test]
    fn cache_dir_follows_the_install_script() {
        let env = Env {
            xdg_cache_home: Some("/x".into()),
            home: Some("/h".into()),
            ..Env::default()
        };
        assert_eq!(env.cache_dir().unwrap(), Path::new("/x/fbsynth"));
        let env = Env {
            xdg_cache_home: None,
            ..env
        };
        assert_eq!(env.cache_dir().unwrap(), Path::new("/h/.cache/fbsynth"));
        let env = Env {
            fbsynth_cache: Some("/c".into()),
            ..env
        };
        assert_eq!(env.cache_dir().unwrap(), Path::new("/c"));
    }

    #[test]
    fn nothing_found_says_how_to_install() {
        let f = Fakes::new();
        let env = Env {
            path: Some(f.path("empty").into()),
            home: Some(f.path("home").into()),
            ..f.env()
        };
        let err = locate_in(None, &env).unwrap_err();
        assert_eq!(
            err.to_string(),
            "NuSMV not found: run .ci/install-nusmv.sh, or pass --nusmv PATH / set NUSMV"
        );
    }
}
