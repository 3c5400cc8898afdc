//! The harness every integration test uses: temporary folders ([`Dir`]), the `synth` binary as
//! a command ([`TestCommand`], [`synth`], [`synth_in`]) and its output as text ([`text`],
//! [`stderr`]), external tools that are skipped where missing but required under `CI=true`
//! ([`nusmv_or_skip`], [`tool_or_skip`]), and the generators and validators several test files
//! share.

use fbsynth::ecc::{Ecc, Run};
use fbsynth::nusmv::Nusmv;
use fbsynth::scenario::{Origin, Scenario, ScenarioSet, Step};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::ffi::OsStr;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

pub use fbsynth::ecc::random::random_ecc;

/// The repository root: the folder `synth` runs in unless a test says otherwise, so that
/// paths such as `tests/data/...` and `specs/...` resolve.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A temporary folder, removed with everything in it when dropped.
pub struct Dir(tempfile::TempDir);

impl Dir {
    /// A new empty folder under the system's temporary folder.
    pub fn new() -> Dir {
        Dir(tempfile::tempdir().expect("create a temporary folder"))
    }

    /// Where the folder is.
    pub fn path(&self) -> &Path {
        self.0.path()
    }
}

/// A run of a binary of this package, set up by builder methods and run by [`output`] or
/// [`spawn`]. Starts in [`root`] with the environment of the test.
///
/// [`output`]: TestCommand::output
/// [`spawn`]: TestCommand::spawn
pub struct TestCommand {
    cmd: Command,
    /// Given as `--nusmv <path>` after every other argument, where every subcommand takes it.
    nusmv: Option<PathBuf>,
}

impl TestCommand {
    /// The user's binary, `synth`.
    pub fn new() -> TestCommand {
        TestCommand::of(env!("CARGO_BIN_EXE_synth"))
    }

    /// The developer binary, `synth-dev` (`generate`, `bench-*`, `experiment`).
    pub fn developer() -> TestCommand {
        TestCommand::of(env!("CARGO_BIN_EXE_synth-dev"))
    }

    fn of(binary: &str) -> TestCommand {
        let mut cmd = Command::new(binary);
        cmd.current_dir(root());
        TestCommand { cmd, nusmv: None }
    }

    /// Adds one argument.
    pub fn arg(&mut self, arg: impl AsRef<OsStr>) -> &mut TestCommand {
        self.cmd.arg(arg);
        self
    }

    /// Adds arguments.
    pub fn args<I>(&mut self, args: I) -> &mut TestCommand
    where
        I: IntoIterator,
        I::Item: AsRef<OsStr>,
    {
        self.cmd.args(args);
        self
    }

    /// Runs in `dir` instead of [`root`].
    pub fn current_dir(&mut self, dir: impl AsRef<Path>) -> &mut TestCommand {
        self.cmd.current_dir(dir);
        self
    }

    /// Sets an environment variable of the run.
    pub fn env(&mut self, key: impl AsRef<OsStr>, value: impl AsRef<OsStr>) -> &mut TestCommand {
        self.cmd.env(key, value);
        self
    }

    /// Checks with the NuSMV at `path` (`--nusmv`, put after the other arguments).
    pub fn nusmv(&mut self, path: &Path) -> &mut TestCommand {
        self.nusmv = Some(path.to_path_buf());
        self
    }

    /// Runs under the file mode creation mask `mask`.
    pub fn umask(&mut self, mask: libc::mode_t) -> &mut TestCommand {
        // SAFETY: umask is async-signal-safe; nothing else runs between fork and exec.
        unsafe {
            self.cmd.pre_exec(move || {
                libc::umask(mask);
                Ok(())
            });
        }
        self
    }

    /// Runs with at most `bytes` of address space (what `ulimit -v` sets).
    pub fn address_space(&mut self, bytes: u64) -> &mut TestCommand {
        // SAFETY: setrlimit is async-signal-safe and reads only the struct on this stack.
        unsafe {
            self.cmd.pre_exec(move || {
                let limit = libc::rlimit {
                    rlim_cur: bytes,
                    rlim_max: bytes,
                };
                match libc::setrlimit(libc::RLIMIT_AS, &limit) {
                    0 => Ok(()),
                    _ => Err(std::io::Error::last_os_error()),
                }
            });
        }
        self
    }

    /// Where the run's standard input comes from (for [`spawn`](TestCommand::spawn)).
    pub fn stdin(&mut self, cfg: Stdio) -> &mut TestCommand {
        self.cmd.stdin(cfg);
        self
    }

    /// Where the run's standard output goes (for [`spawn`](TestCommand::spawn)).
    pub fn stdout(&mut self, cfg: Stdio) -> &mut TestCommand {
        self.cmd.stdout(cfg);
        self
    }

    /// Where the run's standard error goes (for [`spawn`](TestCommand::spawn)).
    pub fn stderr(&mut self, cfg: Stdio) -> &mut TestCommand {
        self.cmd.stderr(cfg);
        self
    }

    /// Runs to the end; its exit status and everything it printed.
    pub fn output(&mut self) -> Output {
        self.last_args();
        self.cmd.output().expect("run the binary under test")
    }

    /// Starts the run and returns at once.
    pub fn spawn(&mut self) -> Child {
        self.last_args();
        self.cmd.spawn().expect("start the binary under test")
    }

    fn last_args(&mut self) {
        if let Some(nusmv) = self.nusmv.take() {
            self.cmd.arg("--nusmv").arg(nusmv);
        }
    }
}

/// Runs `synth` with `args` in [`root`].
pub fn synth(args: &[&str]) -> Output {
    TestCommand::new().args(args).output()
}

/// Runs `synth` with `args` in `dir`.
pub fn synth_in(dir: &Path, args: &[&str]) -> Output {
    TestCommand::new().current_dir(dir).args(args).output()
}

/// Printed bytes as text.
/// The JSON Schema `synth schema` prints with `args` (`--summary`: the summaries' schema),
/// written into `dir` (`machine.schema.json`, `summary.schema.json`) and compiled by boon
/// (draft 2020-12).
pub fn printed_schema(dir: &Path, args: &[&str]) -> (boon::Schemas, boon::SchemaIndex) {
    let name = if args.contains(&"--summary") {
        "summary"
    } else {
        "machine"
    };
    let file = dir.join(format!("{name}.schema.json"));
    let mut all = vec!["schema", "-o", file.to_str().unwrap()];
    all.extend_from_slice(args);
    let o = synth_in(dir, &all);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let mut schemas = boon::Schemas::new();
    let index = boon::Compiler::new()
        .compile(file.to_str().unwrap(), &mut schemas)
        .expect("the schema compiles");
    (schemas, index)
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// What a run printed on stderr, without the line break at its end.
pub fn stderr(o: &Output) -> String {
    text(&o.stderr).trim().to_string()
}

/// Records `runs` random runs of `len` steps of `ecc` as scenarios.
pub fn record(ecc: &Ecc, seed: u64, runs: usize, len: usize) -> ScenarioSet {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let scenarios = (0..runs)
        .map(|r| {
            let mut run = Run::new(ecc);
            let steps = (0..len)
                .map(|_| {
                    let x: Vec<bool> = (0..ecc.inputs.len())
                        .map(|_| rng.gen_bool(0.5))
                        .collect::<Vec<bool>>();
                    let fired = run.step(&x).is_some();
                    Step {
                        inputs: x,
                        outputs: fired.then(|| run.outputs.clone()),
                    }
                })
                .collect();
            Scenario {
                origin: Origin {
                    file: PathBuf::from("random"),
                    line: r + 2,
                    rows: None,
                },
                steps,
            }
        })
        .collect();
    ScenarioSet {
        inputs: ecc.inputs.clone(),
        outputs: ecc.outputs.clone(),
        initial_outputs: ecc.initial_outputs.clone(),
        scenarios,
    }
}

/// NuSMV where `synth` finds it ([`fbsynth::nusmv::locate`]: `$NUSMV`, the PATH, the install
/// script's cache); see [`or_skip`] for when it is missing.
pub fn nusmv_or_skip() -> Option<Nusmv> {
    let found = fbsynth::nusmv::locate(None).map_err(|e| e.to_string());
    or_skip("NuSMV", ".ci/install-nusmv.sh", found).map(Nusmv::new)
}

/// An external tool from the variable `env` or the PATH (`name`), installed in CI by
/// `installer`; see [`or_skip`] for when it is missing.
pub fn tool_or_skip(env: &str, name: &str, installer: &str) -> Option<PathBuf> {
    let found = std::env::var_os(env)
        .map(PathBuf::from)
        .filter(|p| p.is_file())
        .or_else(|| which::which(name).ok())
        .ok_or_else(|| format!("no {name} (set {env} or put it on the PATH)"));
    or_skip(name, installer, found)
}

/// The tool `found`, or `None` after a note that the test is skipped, because it is missing.
/// Under `CI=true` a missing tool fails the test instead: CI installs every tool with
/// `installer`, so a skip there would hide a broken install.
fn or_skip(name: &str, installer: &str, found: Result<PathBuf, String>) -> Option<PathBuf> {
    match found {
        Ok(path) => Some(path),
        Err(why) if std::env::var("CI").as_deref() == Ok("true") => {
            panic!("{name} is required when CI=true ({installer} installs it), but: {why}")
        }
        Err(why) => {
            eprintln!("skipping: {why}");
            None
        }
    }
}

/// Validates `file` with xmllint against `schema` (a file in tests/schemas/: `.xsd` is an XML
/// Schema, `.rng` a RELAX NG grammar, `.dtd` a DTD); the verdict and xmllint's messages.
/// `--nonet`: a DOCTYPE's address on the web is never fetched, the given schema decides.
pub fn xmllint(xmllint: &Path, schema: &str, file: &Path) -> (bool, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/schemas")
        .join(schema);
    let option = match path.extension().and_then(|e| e.to_str()) {
        Some("xsd") => "--schema",
        Some("rng") => "--relaxng",
        Some("dtd") => "--dtdvalid",
        _ => panic!("{schema}: not a schema xmllint reads"),
    };
    let o = Command::new(xmllint)
        .args(["--noout", "--nonet", option])
        .arg(&path)
        .arg(file)
        .output()
        .expect("run xmllint");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}
