//! Which command wrote a run directory, from the files it holds (and, where two commands
//! write a file of the same name, from the keys inside it).

use std::path::Path;

use super::json_view::read_json_file;
use super::ReportError;

/// The kinds of run directory `glassscan report` reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunKind {
    /// `glassscan study scan-angle --out DIR`: `summary.json` with `angles`.
    Study,
    /// `glassscan sweep --out DIR`: `cells.json`.
    Sweep,
    /// `glassscan locate --out DIR`: `summary.json` with `bip_error_mm`, and `bips.csv`.
    Locate,
    /// `glassscan dataset --out DIR`: `run.json` and `manifest.jsonl`.
    Dataset,
}

impl RunKind {
    /// What the page calls it.
    pub fn name(self) -> &'static str {
        match self {
            RunKind::Study => "scan-angle study",
            RunKind::Sweep => "settings sweep",
            RunKind::Locate => "locate run",
            RunKind::Dataset => "dataset",
        }
    }
}

/// What a run directory must hold, for messages.
const EXPECTED: &str = "expected the output directory of `glassscan study scan-angle --out`, \
     `sweep --out` or `locate --out` (summary.json or cells.json), or a dataset (run.json and \
     manifest.jsonl)";

/// The kind of the run in `dir`.
pub fn detect(dir: &Path) -> Result<RunKind, ReportError> {
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(ReportError::input(
                dir,
                format!("not a directory: {EXPECTED}"),
            ))
        }
        Err(e) => return Err(ReportError::input(dir, format!("{e}: {EXPECTED}"))),
    }
    if dir.join("run.json").is_file() {
        return Ok(RunKind::Dataset);
    }
    if dir.join("cells.json").is_file() {
        return Ok(RunKind::Sweep);
    }
    let summary = dir.join("summary.json");
    if summary.is_file() {
        let v = read_json_file(&summary, "the summary.json of a study or locate run")?;
        if v.get("angles").is_some() {
            return Ok(RunKind::Study);
        }
        if v.get("bip_error_mm").is_some() {
            return Ok(RunKind::Locate);
        }
        return Err(ReportError::input(
            &summary,
            "expected the summary of `glassscan study scan-angle --out` (with \"angles\") or of \
             `glassscan locate --out` (with \"bip_error_mm\"), found neither key",
        ));
    }
    if dir.join("manifest.json").is_file() {
        return Err(ReportError::input(
            dir,
            format!(
                "holds a `glassscan scan` run (manifest.json), which has no report; {EXPECTED}"
            ),
        ));
    }
    Err(ReportError::input(
        dir,
        format!("no run files found: {EXPECTED}"),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_by_their_files_and_clear_refusals() {
        let root = tempfile::tempdir().unwrap();
        let dir = |name: &str, files: &[(&str, &str)]| {
            let d = root.path().join(name);
            std::fs::create_dir(&d).unwrap();
            for (f, text) in files {
                std::fs::write(d.join(f), text).unwrap();
            }
            d
        };
        let study = dir("study", &[("summary.json", "{\"angles\": []}")]);
        assert_eq!(detect(&study).unwrap(), RunKind::Study);
        let locate = dir("locate", &[("summary.json", "{\"bip_error_mm\": null}")]);
        assert_eq!(detect(&locate).unwrap(), RunKind::Locate);
        let sweep = dir("sweep", &[("cells.json", "{}")]);
        assert_eq!(detect(&sweep).unwrap(), RunKind::Sweep);
        let ds = dir("ds", &[("run.json", "{}")]);
        assert_eq!(detect(&ds).unwrap(), RunKind::Dataset);

        let e = detect(&dir("empty", &[])).unwrap_err().to_string();
        assert!(
            e.contains("empty: no run files found: expected the output directory"),
            "{e}"
        );
        let e = detect(&dir("scan", &[("manifest.json", "{}")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("a `glassscan scan` run"), "{e}");
        let e = detect(&dir("other", &[("summary.json", "{\"x\": 1}")]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("other/summary.json: expected the summary of"),
            "{e}"
        );
        let e = detect(&dir("torn", &[("summary.json", "{\"angles\": [")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("torn/summary.json: line 1 column"), "{e}");
        let e = detect(&root.path().join("none")).unwrap_err().to_string();
        assert!(e.contains("none: No such file"), "{e}");
    }
}
