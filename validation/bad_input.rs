//! The bad-input matrix (issue 12): every case a user or an adversary met, run against an
//! output directory that already holds a finished run, with `--force`. Each must exit 2, name
//! the file or flag and what is wrong, and leave every existing output byte for byte as it was.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn glassscan(args: &[String]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glassscan"))
        .args(args)
        .current_dir(ROOT)
        .output()
        .expect("the glassscan binary runs")
}

/// Every file under `dir` (relative path → bytes).
fn tree(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.insert(
                    p.strip_prefix(dir).unwrap().to_path_buf(),
                    std::fs::read(&p).unwrap(),
                );
            }
        }
    }
    out
}

/// `flat_panel.toml` with `from` replaced by `to` (which must occur once), written to `dir/name`.
fn edited_scene(dir: &Path, name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(Path::new(ROOT).join("scenes/flat_panel.toml")).unwrap();
    assert_eq!(text.matches(from).count(), 1, "{from:?}");
    let path = dir.join(name);
    std::fs::write(&path, text.replace(from, to)).unwrap();
    path.display().to_string()
}

/// `flat_panel.toml` with one more object: the glTF (or GLB) file `mesh`.
fn mesh_scene(dir: &Path, name: &str, mesh: &Path) -> String {
    let text = std::fs::read_to_string(Path::new(ROOT).join("scenes/flat_panel.toml")).unwrap();
    let object = format!(
        "\n[[objects]]\nname = \"part\"\nmaterial = \"soda_lime\"\nmesh = {{ file = \"{}\" }}\n",
        mesh.display()
    );
    // Objects must come before [target] and later tables; put it first among the objects.
    let at = text.find("[[objects]]").expect("an object");
    let path = dir.join(name);
    std::fs::write(&path, format!("{}{object}\n{}", &text[..at], &text[at..])).unwrap();
    path.display().to_string()
}

struct Case {
    what: &'static str,
    args: Vec<String>,
    /// Words the message must hold: the culprit (file or flag) and what is wrong.
    needles: Vec<String>,
}

#[test]
fn every_bad_input_exits_2_names_the_culprit_and_leaves_existing_output_intact() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = dir.join("out");
    let o = glassscan(&[
        "scan".into(),
        "scenes/flat_panel.toml".into(),
        "--out".into(),
        out.display().to_string(),
        "--poses".into(),
        "2".into(),
        "--photons".into(),
        "4096".into(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let before = tree(&out);

    // Inputs the cases need.
    std::fs::write(dir.join("empty.glb"), b"").unwrap();
    std::fs::write(dir.join("truncated.glb"), b"glTF\x02\0\0").unwrap();
    std::fs::write(
        dir.join("no_bin.gltf"),
        br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"missing.bin","byteLength":12}]}"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("far.csv"),
        "x_mm,y_mm,z_mm\n1e300,0,0\n1,2,3\n4,5,6\n",
    )
    .unwrap();
    let huge = edited_scene(
        dir,
        "huge.toml",
        "thickness_mm = 4 ",
        "thickness_mm = 1e300 ",
    );
    let corner = edited_scene(
        dir,
        "corner.toml",
        "corner_radius_mm = 5",
        "corner_radius_mm = 0.5",
    );
    let long_name = "w".repeat(5_000_000);
    let long = edited_scene(
        dir,
        "long.toml",
        "object = \"pane\"",
        &format!("object = \"{long_name}\""),
    );
    let unknown = edited_scene(dir, "unknown.toml", "thickness_mm = 4 ", "thicknes_mm = 4 ");
    let empty_glb = mesh_scene(dir, "empty_glb.toml", &dir.join("empty.glb"));
    let trunc_glb = mesh_scene(dir, "trunc_glb.toml", &dir.join("truncated.glb"));
    let no_bin = mesh_scene(dir, "no_bin.toml", &dir.join("no_bin.gltf"));

    let o_s = out.display().to_string();
    let far_csv = dir.join("far.csv").display().to_string();
    let not_utf8_csv = dir.join("not_utf8.csv").display().to_string();
    std::fs::write(&not_utf8_csv, b"x_mm,y_mm,z_mm\n\xff\xfe\n").unwrap();
    let scan = |scene: &str, extra: &[&str]| {
        let mut a: Vec<String> = ["scan", scene, "--out", &o_s, "--force"]
            .map(String::from)
            .to_vec();
        a.extend(extra.iter().map(|s| s.to_string()));
        if !extra.contains(&"--poses") {
            a.extend(["--poses".to_string(), "1".to_string()]);
        }
        a
    };
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let fp = "scenes/flat_panel.toml";
    let cases = vec![
        Case {
            what: "poses beyond u32",
            args: scan(fp, &["--poses", "4000000000"]),
            needles: s(&["--poses", "1..=1000000"]),
        },
        Case {
            what: "poses above the scene file's cap",
            args: scan(fp, &["--poses", "2000000"]),
            needles: s(&["--poses", "1..=1000000"]),
        },
        Case {
            what: "photons = u64::MAX",
            args: scan(fp, &["--photons", "18446744073709551615"]),
            needles: s(&["--photons", "2^40"]),
        },
        Case {
            what: "depth beyond the sampler",
            args: scan(fp, &["--max-depth", "100000"]),
            needles: s(&["--max-depth", "1..=4096"]),
        },
        Case {
            what: "negative scan angle",
            args: scan(fp, &["--scan-angle-deg", "-5"]),
            needles: s(&["--scan-angle-deg", "got -5"]),
        },
        Case {
            what: "negative exposure",
            args: scan(fp, &["--exposure-ms", "-1"]),
            needles: s(&["--exposure-ms", "> 0"]),
        },
        Case {
            what: "seed not a number",
            args: scan(fp, &["--seed", "abc"]),
            needles: s(&["--seed", "abc"]),
        },
        Case {
            what: "thickness beyond f32",
            args: scan(&huge, &[]),
            needles: s(&["huge.toml:", "thickness_mm", "1e300"]),
        },
        Case {
            what: "corner radius inside the edge finish",
            args: scan(&corner, &[]),
            needles: s(&["corner.toml:", "corner_radius_mm", "0.8 mm", "0.5 mm"]),
        },
        Case {
            what: "a 5 MB target name",
            args: scan(&long, &[]),
            needles: s(&["long.toml:", "target.object", "(5000000 characters)"]),
        },
        Case {
            what: "unknown scene key",
            args: scan(&unknown, &[]),
            needles: s(&["unknown.toml:", "thicknes_mm"]),
        },
        Case {
            what: "empty GLB",
            args: scan(&empty_glb, &[]),
            needles: s(&["empty.glb", "the file is empty"]),
        },
        Case {
            what: "truncated GLB",
            args: scan(&trunc_glb, &[]),
            needles: s(&["truncated.glb", "truncated GLB"]),
        },
        Case {
            what: "missing external buffer",
            args: scan(&no_bin, &[]),
            needles: s(&["no_bin.gltf", "missing.bin", "does not exist"]),
        },
        Case {
            what: "register points at 1e300",
            args: s(&["register", fp, &far_csv]),
            needles: s(&["far.csv:2", "x_mm"]),
        },
        Case {
            what: "locate with too many poses",
            args: s(&[
                "locate",
                fp,
                "--poses",
                "4000000000",
                "--out",
                &o_s,
                "--force",
            ]),
            needles: s(&["--poses", "3..=1000000"]),
        },
        Case {
            what: "merge of a missing directory",
            args: s(&["merge", "/nonexistent-dataset"]),
            needles: s(&["/nonexistent-dataset", "expected a dataset directory"]),
        },
        Case {
            what: "register points in a file that is not UTF-8",
            args: s(&["register", fp, &not_utf8_csv]),
            needles: s(&["not_utf8.csv", "valid UTF-8"]),
        },
        Case {
            what: "scenes export into a file",
            args: s(&["scenes", "export", "edge_study.toml", &far_csv]),
            needles: s(&[&far_csv, "is a file, expected a directory"]),
        },
        Case {
            what: "verify of a run directory that is no dataset",
            args: s(&["verify", &o_s]),
            needles: s(&[&o_s, "run.json"]),
        },
    ];
    let n = cases.len();
    for case in cases {
        let o = glassscan(&case.args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{}: {err}", case.what);
        for needle in &case.needles {
            assert!(
                err.contains(needle.as_str()),
                "{}: no {needle:?} in: {err}",
                case.what
            );
        }
        assert!(
            err.len() < 2000,
            "{}: a {}-byte message",
            case.what,
            err.len()
        );
        assert!(
            tree(&out) == before,
            "{}: the existing output changed",
            case.what
        );
    }
    assert!(n >= 18);
}
