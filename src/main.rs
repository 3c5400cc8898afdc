//! The `synth` binary: a thin wrapper around [`fbsynth::cli`].

fn main() {
    // Like other command-line tools, end quietly when the reader of stdout goes away
    // (`synth ... | head`) instead of failing on the broken pipe.
    #[cfg(unix)]
    // SAFETY: setting a signal disposition to its default before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    std::process::exit(fbsynth::cli::run());
}
