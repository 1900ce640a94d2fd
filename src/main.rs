//! The `glassscan` command line: everything lives in `glassscan::cli`.

fn main() -> std::process::ExitCode {
    glassscan::cli::run()
}
