//! The `synth` binary: a thin wrapper around [`fbsynth::cli`].

fn main() {
    std::process::exit(fbsynth::cli::run());
}
