//! Progress bars for runs longer than a second (indicatif), on stderr. Hidden when the user
//! asked for `--json`, or when stdout or stderr is not a terminal (CI logs, pipes, redirected
//! output), so that scripted runs print nothing but their results.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

/// A bar counting `len` steps of `what` ("poses", "samples", "cases"), or a hidden one when
/// `quiet` or when stdout or stderr is not a terminal.
pub fn bar(len: u64, what: &str, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() || !std::io::stdout().is_terminal() {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new(len);
    let template =
        format!("{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {what} (eta {{eta}}) {{msg}}");
    pb.set_style(
        ProgressStyle::with_template(&template)
            .expect("the template is valid")
            .progress_chars("=> "),
    );
    pb
}
