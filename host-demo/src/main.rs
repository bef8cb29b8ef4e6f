//! The `smoothtri` command-line tool.

fn main() -> std::process::ExitCode {
    smoothtri_demo::cli::main()
}
