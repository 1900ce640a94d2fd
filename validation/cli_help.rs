//! The command line explaining itself and working from any directory: help with EXAMPLES and
//! EXIT STATUS for every subcommand, completions, man pages, the shipped scenes and suites by
//! name, progress off a terminal and `-q`.

use std::path::Path;

use clap::CommandFactory;
use glassscan::cli::Cli;

use crate::binary::{glassscan_in, stderr, stdout};

/// Runs glassscan in `cwd` (stdin, stdout and stderr are pipes: not a terminal).
fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every subcommand path of the clap tree (`["scan"]`, `["study", "scan-angle"]`, …), `help`
/// left out.
fn subcommand_paths() -> Vec<Vec<String>> {
    fn walk(cmd: &clap::Command, prefix: &[String], out: &mut Vec<Vec<String>>) {
        for sub in cmd.get_subcommands() {
            if sub.get_name() == "help" {
                continue;
            }
            let mut path = prefix.to_vec();
            path.push(sub.get_name().to_string());
            out.push(path.clone());
            walk(sub, &path, out);
        }
    }
    let mut out = Vec::new();
    walk(&Cli::command(), &[], &mut out);
    out
}

/// Every file under `dir`, as paths relative to the repository root with `/`.
fn files_under(dir: &str) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap();
                out.push(rel.to_str().unwrap().replace('\\', "/"));
            }
        }
    }
    let mut out = Vec::new();
    walk(repo(), &repo().join(dir), &mut out);
    out.sort();
    out
}

#[test]
fn every_subcommand_s_help_has_examples_and_exit_status() {
    let paths = subcommand_paths();
    for want in [
        &["scan"][..],
        &["study", "scan-angle"],
        &["scenes", "export"],
        &["man"],
    ] {
        assert!(
            paths.iter().any(|p| p == want),
            "{want:?} missing: {paths:?}"
        );
    }
    let mut all = vec![Vec::new()];
    all.extend(paths);
    for path in all {
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let o = glassscan_in(repo(), &args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let help = stdout(&o);
        for needle in [
            "EXAMPLES:",
            "EXIT STATUS:",
            "    0  success",
            "    2  bad input",
        ] {
            assert!(
                help.contains(needle),
                "{args:?} --help lacks {needle:?}:\n{help}"
            );
        }
        // The examples run glassscan itself (on shipped scenes by name where a scene is used).
        let examples = help.split("EXAMPLES:").nth(1).unwrap();
        let commands: Vec<&str> = examples
            .lines()
            .take_while(|l| !l.starts_with("EXIT STATUS"))
            .filter(|l| l.trim_start().starts_with("glassscan "))
            .collect();
        assert!(!commands.is_empty(), "{args:?}");
        for c in commands {
            assert!(
                !c.split_whitespace().any(|w| w.starts_with("scenes/")),
                "{args:?}: shipped scenes by name: {c}"
            );
        }
    }
}

#[test]
fn override_flags_say_their_default() {
    let o = glassscan_in(repo(), &["scan", "--help"]);
    let help = stdout(&o);
    for (flag, says) in [
        (
            "--scan-angle-deg",
            "overrides [scan].scan_angle_deg. Default: the scene's (40 in edge_study",
        ),
        (
            "--poses",
            "overrides [scan].poses. Default: the scene's (4 in edge_study",
        ),
        (
            "--exposure-ms",
            "overrides [sensor].exposure_ms. Default: the scene's (0.5 in edge_study",
        ),
        ("--photons", "[default: 262144]"),
    ] {
        let from = help
            .find(&format!("      {flag} "))
            .unwrap_or_else(|| panic!("{flag}"));
        let text: String = help[from..]
            .split("\n\n")
            .take(2)
            .collect::<Vec<_>>()
            .join(" ");
        let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(text.contains(says), "{flag}: {text}");
    }
    let o = glassscan_in(repo(), &["check", "--help"]);
    assert!(stdout(&o).contains("[default: fast]"), "{}", stdout(&o));
}

#[test]
fn completions_for_bash_zsh_and_fish_name_the_subcommands() {
    for shell in ["bash", "zsh", "fish"] {
        let o = glassscan_in(repo(), &["completions", shell]);
        assert!(o.status.success(), "{shell}: {}", stderr(&o));
        let script = stdout(&o);
        assert!(script.len() > 1000, "{shell}: {} bytes", script.len());
        for word in [
            "scan",
            "locate",
            "scenes",
            "scan-angle",
            "exposure-ms",
            "quiet",
        ] {
            assert!(script.contains(word), "{shell} completion lacks {word}");
        }
    }
    let o = glassscan_in(repo(), &["completions", "tcsh"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bash"), "{}", stderr(&o));
}

#[test]
fn man_writes_one_page_per_command_with_examples_and_exit_status() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("man1");
    let o = glassscan_in(tmp.path(), &["man", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut names = vec!["glassscan.1".to_string()];
    names.extend(
        subcommand_paths()
            .iter()
            .map(|p| format!("glassscan-{}.1", p.join("-"))),
    );
    let mut written: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    written.sort();
    names.sort();
    assert_eq!(written, names);
    for name in &names {
        let page = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(page.starts_with(".ie") || page.contains("\n.TH "), "{name}");
        for needle in [
            ".SH EXAMPLES\n.nf\n",
            ".SH EXIT STATUS\n.nf\n",
            ".SH SYNOPSIS",
        ] {
            assert!(page.contains(needle), "{name} lacks {needle:?}");
        }
    }
    let scan = std::fs::read_to_string(dir.join("glassscan-scan.1")).unwrap();
    assert!(
        scan.contains("glassscan scan edge_study \\-\\-out out/edge"),
        "{scan}"
    );
}

#[test]
fn scenes_list_names_every_shipped_file_and_they_are_the_repository_s() {
    let mut on_disk = files_under("scenes");
    on_disk.extend(files_under("validation/check"));
    on_disk.sort();
    let mut shipped: Vec<String> = glassscan::shipped::FILES
        .iter()
        .map(|f| f.path.to_string())
        .collect();
    shipped.sort();
    assert_eq!(
        shipped, on_disk,
        "src/shipped.rs FILES must list exactly these"
    );

    let tmp = tempfile::tempdir().unwrap();
    let o = glassscan_in(tmp.path(), &["scenes", "list"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let listing = stdout(&o);
    for f in &on_disk {
        assert!(
            listing.lines().any(|l| l.contains(&format!(" {f} "))),
            "{f} not listed:\n{listing}"
        );
    }
    let o = glassscan_in(tmp.path(), &["scenes", "list", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let scenes: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "scene")
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert!(scenes.contains(&"edge_study") && scenes.contains(&"car_side_window"));
    assert!(!scenes.contains(&"randomize_edge_study.toml"));
}

#[test]
fn export_round_trips_byte_for_byte_and_refuses_to_overwrite_a_changed_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("all");
    let o = glassscan_in(tmp.path(), &["scenes", "export", "all", "all"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in glassscan::shipped::FILES {
        let inside = f
            .path
            .strip_prefix("scenes/")
            .or_else(|| f.path.strip_prefix("validation/check/"))
            .unwrap();
        assert_eq!(
            std::fs::read(dir.join(inside)).unwrap(),
            std::fs::read(repo().join(f.path)).unwrap(),
            "{}",
            f.path
        );
    }
    // One scene by name; again into the same place is fine (identical).
    for _ in 0..2 {
        let o = glassscan_in(tmp.path(), &["scenes", "export", "edge_study", "one"]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let copy = tmp.path().join("one/edge_study.toml");
    assert_eq!(
        std::fs::read(&copy).unwrap(),
        std::fs::read(repo().join("scenes/edge_study.toml")).unwrap()
    );
    // An edited copy is kept unless --force.
    std::fs::write(&copy, "# mine\n").unwrap();
    let o = glassscan_in(tmp.path(), &["scenes", "export", "edge_study", "one"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&copy).unwrap(), "# mine\n");
    let o = glassscan_in(
        tmp.path(),
        &["scenes", "export", "edge_study", "one", "--force"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&copy).unwrap(),
        std::fs::read(repo().join("scenes/edge_study.toml")).unwrap()
    );
    // The exported file is a scene file like any other.
    let o = glassscan_in(
        tmp.path(),
        &[
            "scan",
            "one/edge_study.toml",
            "--out",
            "run",
            "--poses",
            "1",
            "--photons",
            "4096",
            "-v",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("one/edge_study.toml: the scene file on disk"));
}

#[test]
fn scan_by_name_from_another_directory_with_progress_lines_and_quiet() {
    let tmp = tempfile::tempdir().unwrap();
    let args = |out: &'static str| {
        vec![
            "scan",
            "flat_opaque",
            "--out",
            out,
            "--poses",
            "2",
            "--photons",
            "20000",
        ]
    };
    let o = glassscan_in(tmp.path(), &args("run"));
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    // Off a terminal: one plain line per pose, named as its files.
    let lines: Vec<&str> = err.lines().filter(|l| l.contains(" done (")).collect();
    assert_eq!(lines.len(), 2, "{err}");
    assert!(lines[0].starts_with("pose_000 done (1/2, "), "{err}");
    assert!(lines[1].starts_with("pose_001 done (2/2, "), "{err}");
    assert!(lines[1].contains(" s): ") && lines[1].contains("profile points valid"));
    assert!(tmp.path().join("run/pose_001_profile.csv").is_file());
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("run/manifest.json")).unwrap())
            .unwrap();
    assert_eq!(manifest["scene"], "scenes/flat_opaque.toml");
    // The same bits as the repository's file, read from disk at the root.
    let at_root = glassscan_in(
        repo(),
        &[
            "scan",
            "scenes/flat_opaque.toml",
            "--out",
            tmp.path().join("root").to_str().unwrap(),
            "--poses",
            "2",
            "--photons",
            "20000",
        ],
    );
    assert!(at_root.status.success(), "{}", stderr(&at_root));
    assert_eq!(
        std::fs::read(tmp.path().join("run/pose_001_profile.csv")).unwrap(),
        std::fs::read(tmp.path().join("root/pose_001_profile.csv")).unwrap()
    );
    // -q: no progress, no summary; still the files.
    let mut quiet = args("quiet");
    quiet.insert(0, "-q");
    let o = glassscan_in(tmp.path(), &quiet);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o), "", "-q prints nothing on success");
    assert!(tmp.path().join("quiet/manifest.json").is_file());
    // -v says where the scene came from.
    let mut verbose = args("verbose");
    verbose.push("-v");
    let o = glassscan_in(tmp.path(), &verbose);
    assert!(
        stderr(&o).contains("scenes/flat_opaque.toml: the scene shipped in glassscan"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn unknown_names_exit_2_listing_the_shipped_ones() {
    let tmp = tempfile::tempdir().unwrap();
    for (args, given, listed) in [
        (
            &["scan", "edge_studdy", "--out", "x"][..],
            "edge_studdy: no such file",
            "shipped scenes: car_side_window, car_side_window_gltf, edge_study, ",
        ),
        (
            &["locate", "nope.toml"],
            "nope.toml: no such file",
            "shipped scenes: car_side_window,",
        ),
        (
            &["study", "scan-angle", "nope"],
            "nope: no such file",
            "shipped scenes: car_side_window,",
        ),
        (
            &["check", "fats"],
            "fats: no such file",
            "shipped suites: fast, full",
        ),
        (
            &["scenes", "export", "edge_studdy", "d"],
            "edge_studdy: glassscan ships no file of that name",
            "edge_study, ",
        ),
    ] {
        let o = glassscan_in(tmp.path(), args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.starts_with(&format!("error: {given}")),
            "{args:?}: {err}"
        );
        assert!(err.contains(listed), "{args:?}: {err}");
    }
    assert!(!tmp.path().join("x").exists() && !tmp.path().join("d").exists());
    // A shipped suite cannot take a new baseline away from the repository (the suite and its
    // baseline are read from the binary before the refusal).
    let o = glassscan_in(tmp.path(), &["check", "fast", "--update-baseline"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("run from the repository root"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn shipped_suites_and_the_study_s_default_scenes_work_from_another_directory() {
    let tmp = tempfile::tempdir().unwrap();
    // A suite whose case names a scene by its repository path, run away from the repository:
    // the case reads the shipped scene (the shipped suites' cases are written the same way).
    let suite = tmp.path().join("tiny.toml");
    std::fs::write(
        &suite,
        "[[case]]\nname = \"plate\"\nscene = \"scenes/flat_opaque.toml\"\nposes = 3\nseed = 1\nphotons = 16384\n",
    )
    .unwrap();
    let o = glassscan_in(tmp.path(), &["check", "tiny.toml", "--update-baseline"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(tmp.path().join("tiny.baseline.json").is_file());
    // The study's default scene and its tape and cover siblings, all shipped.
    let o = glassscan_in(
        tmp.path(),
        &[
            "study",
            "scan-angle",
            "--positions",
            "1",
            "--no-sweep",
            "--no-map",
            "--angles-deg",
            "40",
            "--exposures-ms",
            "0.5",
            "--photons",
            "16384",
            "--json",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["scenes"]["bare"], "scenes/edge_study.toml");
    assert_eq!(v["scenes"]["tape"], "scenes/edge_study_tape.toml");
    assert_eq!(v["scenes"]["cover"], "scenes/edge_study_cover.toml");
}

/// `glassscan check` (the `fast` suite) away from the repository passes against the shipped
/// baseline (6 s on the 2-core machine).
#[test]
fn check_without_a_suite_runs_the_shipped_fast_suite_from_another_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let o = glassscan_in(tmp.path(), &["-v", "check", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("validation/check/fast.toml: not on disk here"),
        "{}",
        stderr(&o)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["suite"], "validation/check/fast.toml");
    assert_eq!(v["regressed"], 0);
    assert_eq!(v["new"], 0, "every case has a shipped baseline");
}
