//! The `cellc` binary.

fn main() -> std::process::ExitCode {
    cellc::dispatch()
}
