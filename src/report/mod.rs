//! `glassscan report RUN_DIR`: one self-contained HTML page of a run — a scan-angle study, a
//! settings sweep, a locate run or a dataset — with its settings, tables and figures, and the
//! paper's numbers beside ours where the paper has them.
//!
//! Everything on the page comes from the run's files: the JSON summaries and CSV tables the
//! commands wrote, and their SVG figures, which are checked and put inline (`figure_file`);
//! a locate run and a dataset, which have no figures of their own, get charts drawn here
//! (`svg`). The page has inline CSS and no script, and fetches nothing.
//!
//! One file per concept: `detect` (which command wrote the directory), `json_view` (reading
//! JSON with errors that name file and place), `format` (numbers), `html` (escaping and the
//! page), `svg` (charts), `xml_check` (well-formedness of what is inlined), `figure_file` (a
//! run's SVG files), `paper` (the paper's numbers and their sources), and one file per kind of
//! run: `study`, `sweep`, `locate`, `dataset`.
//!
//! A directory that is none of these, or whose files are damaged, is an error naming the file
//! and what was expected there ([`ReportError::Input`]); the page is built whole in memory
//! and written atomically, so a failed report never leaves a partial page over an earlier one.

pub mod dataset;
pub mod detect;
pub mod error;
pub mod figure_file;
pub mod format;
pub mod html;
pub mod json_view;
pub mod locate;
pub mod paper;
pub mod study;
pub mod svg;
pub mod sweep;
pub mod xml_check;

use std::io::Read;
use std::path::Path;

pub use detect::RunKind;
pub use error::ReportError;

use crate::io::atomic::write_atomic;
use html::{Cell, Page, Table};
use json_view::Node;

/// The page of the run in `dir`, and its kind.
pub fn build(dir: &Path) -> Result<(RunKind, String), ReportError> {
    let kind = detect::detect(dir)?;
    let page = match kind {
        RunKind::Study => study::page(dir)?,
        RunKind::Sweep => sweep::page(dir)?,
        RunKind::Locate => locate::page(dir)?,
        RunKind::Dataset => dataset::page(dir)?,
    };
    Ok((kind, page))
}

/// Builds the page of the run in `dir` and writes it to `out` atomically (an existing page is
/// replaced only by a complete new one). Returns the kind of run.
///
/// `out` must be new or an earlier page of this command: any other file there (a run's own
/// summary, given as `--out` by mistake) is bad input and stays as it was.
pub fn write_report(dir: &Path, out: &Path) -> Result<RunKind, ReportError> {
    refuse_to_replace_other_files(out)?;
    let (kind, page) = build(dir)?;
    write_atomic(out, |w| w.write_all(page.as_bytes())).map_err(ReportError::Write)?;
    Ok(kind)
}

/// An error unless `out` is free or holds a page of `glassscan report` (its generator tag
/// within the first kilobyte).
fn refuse_to_replace_other_files(out: &Path) -> Result<(), ReportError> {
    let meta = match std::fs::symlink_metadata(out) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(ReportError::input(out, format!("cannot be inspected: {e}"))),
        Ok(m) => m,
    };
    let refuse = |what: &str| {
        ReportError::input(
            out,
            format!(
                "{what}, not a page of `glassscan report`: it is left as it is; \
                 choose another --out"
            ),
        )
    };
    if meta.is_dir() {
        return Err(refuse("is a directory"));
    }
    let mut head = Vec::with_capacity(1024);
    std::fs::File::open(out)
        .and_then(|f| f.take(1024).read_to_end(&mut head))
        .map_err(|e| ReportError::input(out, format!("cannot be read: {e}")))?;
    let generator = html::GENERATOR_META.as_bytes();
    if head.windows(generator.len()).any(|w| w == generator) {
        Ok(())
    } else {
        Err(refuse("exists"))
    }
}

/// The run's settings as a two-column table: each of `keys` (JSON member, label) that `node`
/// has, its value as text.
fn settings_table(node: &Node, keys: &[(&str, &str)]) -> Table {
    let mut t = Table::new(["setting", "value"]);
    for (key, label) in keys {
        if let Some(v) = node.value().get(*key) {
            t.row(vec![Cell::text(*label), Cell::text(format::setting(v))]);
        }
    }
    t
}

/// The SVG files a run lists in its `files` member (in its order), each checked and read.
fn listed_figures(
    dir: &Path,
    files: &Node,
    listed_in: &str,
) -> Result<Vec<(String, String)>, ReportError> {
    let mut out = Vec::new();
    for f in files.array()? {
        let name = f.str()?;
        if name.ends_with(".svg") {
            out.push((
                name.to_owned(),
                figure_file::read_svg(dir, name, listed_in)?,
            ));
        }
    }
    Ok(out)
}

/// Puts every listed figure whose name `matches` into the page (with `caption` of its name) and
/// removes it from `figures`.
fn place_figures(
    page: &mut Page,
    figures: &mut Vec<(String, String)>,
    matches: impl Fn(&str) -> bool,
    caption: impl Fn(&str) -> String,
) {
    let (take, keep): (Vec<_>, Vec<_>) = figures.drain(..).partition(|(n, _)| matches(n));
    *figures = keep;
    for (name, svg) in take {
        page.figure(&svg, &caption(&name));
    }
}
