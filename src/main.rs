//! The `synth` binary: the command line ([`cli`]) over the `fbsynth` library, and the
//! benchmark cases (`synth generate`, `synth bench-noisy`).

// The tests use more of the cases than the commands do.
#[allow(dead_code)]
mod cases;
mod cli;

fn main() {
    // Like other command-line tools, end quietly when the reader of stdout goes away
    // (`synth ... | head`) instead of failing on the broken pipe.
    #[cfg(unix)]
    // SAFETY: setting a signal disposition to its default before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    std::process::exit(cli::run());
}
