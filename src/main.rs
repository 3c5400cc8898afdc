//! The `synth` binary: the command line ([`fbsynth::cli`]) over the `fbsynth` library. The
//! developer's commands (benchmarks, experiments, the generators of the shipped data) are
//! `synth-dev`.

fn main() {
    // SIGPIPE stays ignored (Rust's default): a broken pipe is an error where it happens (NuSMV
    // gone before reading its input), and stdout ignores it (`out!` in `cli`).
    std::process::exit(fbsynth::cli::run());
}
