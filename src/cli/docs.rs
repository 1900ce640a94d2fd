//! `glassscan completions SHELL` (clap_complete) and `glassscan man DIR` (clap_mangen): both
//! made from the same clap command tree as `--help`, so they cannot drift from it.

use std::path::{Path, PathBuf};

use clap::{Args, CommandFactory};
use clap_complete::Shell;

use super::{progress, Cli, CliError};
use crate::io::atomic::write_atomic;

/// Arguments of `glassscan completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum, value_name = "SHELL")]
    pub shell: Shell,
}

/// Arguments of `glassscan man`.
#[derive(Debug, Args)]
pub struct ManArgs {
    /// Directory to write the pages into (created if missing): glassscan.1 and one page per
    /// subcommand (glassscan-scan.1, glassscan-study-scan-angle.1, …); existing pages are
    /// replaced.
    #[arg(value_name = "DIR", default_value = ".")]
    pub dir: PathBuf,
}

/// Prints the completion script for `args.shell` on stdout.
pub fn completions(args: &CompletionsArgs) -> Result<(), CliError> {
    let mut cmd = Cli::command();
    let mut out = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, "glassscan", &mut out);
    use std::io::Write;
    std::io::stdout()
        .write_all(&out)
        .map_err(CliError::internal)
}

/// Writes the man pages into `args.dir`.
pub fn man(args: &ManArgs) -> Result<(), CliError> {
    let pages = man_pages().map_err(CliError::internal)?;
    std::fs::create_dir_all(&args.dir).map_err(|e| {
        CliError::from_file(crate::io::FileError::io(
            &args.dir,
            "create the output directory",
            e,
        ))
    })?;
    crate::io::output_dir::check_writable(&args.dir).map_err(CliError::input)?;
    for (name, text) in &pages {
        let path = args.dir.join(name);
        write_atomic(&path, |w| w.write_all(text.as_bytes())).map_err(CliError::from_file)?;
    }
    if !progress::is_quiet() {
        eprintln!(
            "wrote {} man pages to {} ({}; read one with `man {}`)",
            pages.len(),
            args.dir.display(),
            pages
                .iter()
                .map(|(n, _)| n.as_str())
                .take(3)
                .chain(["…"])
                .collect::<Vec<_>>()
                .join(", "),
            Path::new(&args.dir).join("glassscan.1").display()
        );
    }
    Ok(())
}

/// Every man page, as (file name, roff text): the top command's and one per subcommand at
/// any depth (`help` left out), each with the long help's closing sections (EXAMPLES, EXIT
/// STATUS, …) as man sections of their own.
pub fn man_pages() -> std::io::Result<Vec<(String, String)>> {
    let mut cmd = Cli::command().disable_help_subcommand(true);
    cmd.build();
    let mut pages = Vec::new();
    collect(&cmd, &mut pages)?;
    Ok(pages)
}

fn collect(cmd: &clap::Command, pages: &mut Vec<(String, String)>) -> std::io::Result<()> {
    let extra = cmd
        .get_after_long_help()
        .or_else(|| cmd.get_after_help())
        .map(|s| s.to_string());
    // clap_mangen would fill the closing sections into one paragraph; they are rendered here
    // unfilled under their own headings instead.
    let page = clap_mangen::Man::new(
        cmd.clone()
            .after_help(None::<&'static str>)
            .after_long_help(None::<&'static str>),
    );
    let mut text = Vec::new();
    page.render(&mut text)?;
    let mut text = String::from_utf8(text).expect("roff output is UTF-8");
    if let Some(extra) = extra {
        text.push_str(&sections(&extra));
    }
    pages.push((page.get_filename(), text));
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        collect(sub, pages)?;
    }
    Ok(())
}

/// Closing help text as roff: a line `HEADING:` in capitals starts a section `.SH HEADING`,
/// the lines under it are kept as they are (`.nf`), escaped.
fn sections(help: &str) -> String {
    let mut out = String::new();
    let mut open = false;
    for line in help.lines() {
        let heading = line
            .strip_suffix(':')
            .filter(|h| !h.starts_with(' ') && !h.is_empty() && h == &h.to_uppercase());
        if let Some(h) = heading {
            if open {
                out.push_str(".fi\n");
            }
            out.push_str(&format!(".SH {h}\n.nf\n"));
            open = true;
            continue;
        }
        if !open {
            out.push_str(".SH NOTES\n.nf\n");
            open = true;
        }
        out.push_str(&escape(line));
        out.push('\n');
    }
    if open {
        out.push_str(".fi\n");
    }
    out
}

/// One line of text for roff: backslashes and hyphens escaped, a leading `.` or `'` (a
/// request) protected.
fn escape(line: &str) -> String {
    let s = line.replace('\\', "\\e").replace('-', "\\-");
    if s.starts_with('.') || s.starts_with('\'') {
        format!("\\&{s}")
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closing_sections_become_man_sections_with_escaped_lines() {
        let roff =
            sections("EXAMPLES:\n    glassscan scan x \\\n.hidden\n\nEXIT STATUS:\n    0  ok");
        assert_eq!(
            roff,
            ".SH EXAMPLES\n.nf\n    glassscan scan x \\e\n\\&.hidden\n\n.fi\n.SH EXIT STATUS\n.nf\n    0  ok\n.fi\n"
        );
    }
}
