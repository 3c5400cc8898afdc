//! The `synth` binary: the command line ([`cli`]) over the `fbsynth` library, and the
//! benchmark cases (`synth generate`, `synth bench-noisy`).

// The tests use more of the cases than the commands do.
#[allow(dead_code)]
mod cases;
mod cli;

fn main() {
    // SIGPIPE stays ignored (Rust's default): a broken pipe is an error where it happens (NuSMV
    // gone before reading its input), and stdout ignores it (`out!` in `cli`).
    std::process::exit(cli::run());
}
