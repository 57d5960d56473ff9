//! The `cellc` binary.

fn main() -> std::process::ExitCode {
    // A closed standard output (`cellc graph ... | head`) ends the program quietly with the
    // usual status, as for any Unix tool, instead of a panic on the next write. Rust sets
    // SIGPIPE to "ignore" before `main`; this restores the default action.
    #[cfg(unix)]
    // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid
    // disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    cellc::dispatch()
}
