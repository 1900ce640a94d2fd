//! The long help's closing sections (`--help`, and the man pages made from it): EXAMPLES on
//! shipped scenes and suites, and EXIT STATUS, per subcommand. `validation/cli_help.rs`
//! checks that every subcommand has both.

/// Where the formats and sources are documented, for the top-level help.
const SEE_ALSO: &str = "\
SEE ALSO:
    glassscan scenes export README.md DIR    the scene-file reference (every key, unit,
                                             default and its source; scenes/README.md)
    docs/parameters.md, README.md, ARCHITECTURE.md in the repository";

/// The exit codes every command shares (0 ok, 2 bad input, 1 other failures).
macro_rules! exit_status {
    // Commands with nothing to regress: their only other failure.
    () => {
        exit_status!("an internal error or a failed write (disk full, permission lost mid-run)")
    };
    ($one:literal) => {
        concat!(
            "EXIT STATUS:\n",
            "    0  success\n",
            "    1  ",
            $one,
            "\n",
            "    2  bad input, nothing done: a scene or suite file with a wrong value (the message\n",
            "       names file, line:column, field and what was expected), an unknown scene or\n",
            "       suite name (the message lists the shipped ones), a bad flag, or an output\n",
            "       directory or file it must not write over (see --force or --resume where the\n",
            "       command has them) or cannot write"
        )
    };
}

/// `glassscan --help`.
pub const TOP: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan scenes list                             # the shipped scenes, by name\n",
    "    glassscan scan edge_study --out out/edge          # simulate 4 poses, write images\n",
    "    glassscan locate car_side_window --poses 12       # the paper's pipeline, errors\n",
    "    glassscan study scan-angle --out out/study        # the paper's edge experiment\n",
    "    glassscan report out/study                        # ... as one HTML page\n",
    "    glassscan check                                   # regression suite `fast`\n",
    "    glassscan completions bash > ~/.local/share/bash-completion/completions/glassscan\n",
    "\n",
    "A SCENE argument is a scene file's path or a shipped scene's name (`glassscan scenes\n",
    "list`); a path that exists wins. Shipped scenes and suites work from any directory.\n",
    "`-q` hides progress and notes; off a terminal, progress is one line per step on stderr.\n",
    "\n",
    exit_status!("a regression (check), a damaged dataset (verify), or an internal or I/O error"),
    "\n\n",
);

/// `glassscan --help`, with the pointers to the documentation.
pub fn top() -> String {
    format!("{TOP}{SEE_ALSO}")
}

/// `glassscan scan --help`.
pub const SCAN: &str = concat!(
    "EXAMPLES:\n",
    "    # 4 poses along the border of the shipped edge-study pane (a name, not a path):\n",
    "    glassscan scan edge_study --out out/edge\n",
    "    # 8 poses at 30°, a shorter exposure, another seed; a JSON summary on stdout:\n",
    "    glassscan scan flat_opaque --out out/a30 --scan-angle-deg 30 --poses 8 \\\n",
    "        --exposure-ms 0.01 --seed 7 --json\n",
    "    # The mixed-pixel case, every peak of each column:\n",
    "    glassscan scan mixed_pixels --out out/mixed --poses 1 --peak-select all\n",
    "    # Your own scene file; rerun into the same directory:\n",
    "    glassscan scan my_scene.toml --out out/mine --force\n",
    "\n",
    "Writes pose_NNN.png (16-bit sensor image), pose_NNN.exr (irradiance per path class),\n",
    "pose_NNN_profile.csv and manifest.json. Scene keys: scenes/README.md (`glassscan scenes\n",
    "export README.md DIR`).\n",
    "\n",
    exit_status!(),
);

/// `glassscan locate --help`.
pub const LOCATE: &str = concat!(
    "EXAMPLES:\n",
    "    # The paper's run on the curved side window: 12 BIPs, ICP, errors against truth:\n",
    "    glassscan locate car_side_window --poses 12 --scan-angle-deg 45\n",
    "    # With robot, hand-eye and linearity errors, the opaque copy, and the files:\n",
    "    glassscan locate car_side_window --errors default --opaque-copy \\\n",
    "        --opaque-exposure-ms 0.5 --out out/locate\n",
    "    # The summary as JSON, the paper's BIP rule:\n",
    "    glassscan locate edge_study --bip highest --json\n",
    "\n",
    exit_status!(),
);

/// `glassscan register --help`.
pub const REGISTER: &str = concat!(
    "EXAMPLES:\n",
    "    # Register the BIPs a locate run wrote (same pose as the run found):\n",
    "    glassscan locate car_side_window --out out/locate\n",
    "    glassscan register car_side_window out/locate/bips.csv\n",
    "    # Your own points (x_mm,y_mm,z_mm columns, base frame), as JSON:\n",
    "    glassscan register car_side_window my_points.csv --json\n",
    "\n",
    exit_status!(),
);

/// `glassscan check --help`.
pub const CHECK: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan check                      # the `fast` suite (the default), ~1 min\n",
    "    glassscan check full                 # every case, ~10 min\n",
    "    glassscan check fast --json          # the comparison as JSON\n",
    "    # After a change that is meant, from the repository root:\n",
    "    glassscan check fast --update-baseline\n",
    "    glassscan check my_suite.toml        # your own suite (format: src/check/suite.rs)\n",
    "\n",
    "Shipped suites: fast, full (validation/check/); they run from any directory.\n",
    "\n",
    exit_status!(
        "a metric regressed against the baseline (the table marks it), or an internal error"
    ),
);

/// `glassscan dataset --help`.
pub const DATASET: &str = concat!(
    "EXAMPLES:\n",
    "    # 20 randomised samples of the edge-study pane:\n",
    "    glassscan scenes export randomize_edge_study.toml .\n",
    "    glassscan dataset edge_study --count 20 --out out/ds --photons 65536 \\\n",
    "        --randomize randomize_edge_study.toml --seed 42\n",
    "    # Shard 3 of 8 (or from SLURM_ARRAY_TASK_ID), continuing a killed run:\n",
    "    glassscan dataset edge_study --count 8000 --out /shared/ds --shard 3/8 --resume\n",
    "\n",
    exit_status!(),
);

/// `glassscan merge --help`.
pub const MERGE: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan merge out/ds                       # shards in one directory\n",
    "    glassscan merge node1/ds node2/ds --out out/ds_all\n",
    "\n",
    exit_status!(),
);

/// `glassscan score --help`.
pub const SCORE: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan dataset edge_study --count 20 --out out/ds\n",
    "    glassscan score out/ds my_bips.csv           # sample,x_mm,y_mm,z_mm (base frame)\n",
    "    glassscan score out/ds my_bips.csv --json\n",
    "\n",
    exit_status!(),
);

/// `glassscan study --help`.
pub const STUDY: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan study scan-angle --out out/study\n",
    "    glassscan study scan-angle --positions 4 --sweep-deg 10:80:10 --photons 262144 \\\n",
    "        --no-map --out out/study_quick\n",
    "\n",
    exit_status!(),
);

/// `glassscan study scan-angle --help`.
pub const STUDY_SCAN_ANGLE: &str = concat!(
    "EXAMPLES:\n",
    "    # The whole study on the shipped edge-study scenes (tape, cover, bare), any directory:\n",
    "    glassscan study scan-angle --out out/study\n",
    "    # A quick look: 4 positions, a coarse sweep, no finding map:\n",
    "    glassscan study scan-angle --positions 4 --sweep-deg 10:80:10 --photons 262144 \\\n",
    "        --no-map --out out/study_quick\n",
    "    # Your own pane (my_pane_tape.toml, my_pane_cover.toml beside it are used if present):\n",
    "    glassscan study scan-angle my_pane.toml --angles-deg 10,40 --json\n",
    "\n",
    exit_status!(),
);

/// `glassscan sweep --help`.
pub const SWEEP: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan sweep edge_study --scan-angle-deg 10,40 --exposure-ms 0.05,0.5 \\\n",
    "        --threshold 128,auto --peak-select first,max_intensity --poses 4 --out out/sweep\n",
    "    glassscan sweep car_side_window --scan-angle-deg 30,45,60 --exposure-ms 0.5,2 --json\n",
    "\n",
    exit_status!(),
);

/// `glassscan verify --help`.
pub const VERIFY: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan verify out/ds              # every sample listed, every file's size\n",
    "    glassscan verify out/ds --json\n",
    "\n",
    exit_status!("the dataset is damaged or incomplete (each damaged file is listed)"),
);

/// `glassscan scenes --help`.
pub const SCENES: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan scenes list\n",
    "    glassscan scenes export edge_study my_scenes     # my_scenes/edge_study.toml\n",
    "    glassscan scenes export all my_scenes            # every shipped file\n",
    "\n",
    exit_status!(),
);

/// `glassscan scenes list --help`.
pub const SCENES_LIST: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan scenes list\n",
    "    glassscan scenes list --json | jq -r '.[] | select(.kind == \"scene\") | .name'\n",
    "\n",
    exit_status!(),
);

/// `glassscan scenes export --help`.
pub const SCENES_EXPORT: &str = concat!(
    "EXAMPLES:\n",
    "    # A copy to edit, then scan it:\n",
    "    glassscan scenes export edge_study work\n",
    "    glassscan scan work/edge_study.toml --out out/mine\n",
    "    # The scene-file reference, a randomisation file, a suite with its baseline:\n",
    "    glassscan scenes export README.md docs_here\n",
    "    glassscan scenes export randomize_edge_study.toml work\n",
    "    glassscan scenes export fast suites              # fast.toml, fast.baseline.json\n",
    "    glassscan scenes export all work --force         # everything, overwriting\n",
    "\n",
    exit_status!(),
);

/// `glassscan report --help`.
pub const REPORT: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan study scan-angle --out out/study && glassscan report out/study\n",
    "    #   -> out/study/report.html: settings, tables, figures, the paper's numbers\n",
    "    glassscan locate car_side_window --poses 12 --out out/loc && glassscan report out/loc\n",
    "    glassscan report out/ds --out ds_report.html    # a dataset: settings, draws, points\n",
    "\n",
    "The page is one file (inline SVG and CSS, no script, no network): mail it or open it\n",
    "anywhere. A study, sweep, locate or dataset directory is recognised by its files.\n",
    "\n",
    exit_status!(),
);

/// `glassscan completions --help`.
pub const COMPLETIONS: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan completions bash > ~/.local/share/bash-completion/completions/glassscan\n",
    "    glassscan completions zsh > ~/.zfunc/_glassscan      # with fpath+=(~/.zfunc)\n",
    "    glassscan completions fish > ~/.config/fish/completions/glassscan.fish\n",
    "    glassscan completions powershell >> $PROFILE\n",
    "\n",
    exit_status!(),
);

/// `glassscan man --help`.
pub const MAN: &str = concat!(
    "EXAMPLES:\n",
    "    glassscan man out/man && man out/man/glassscan-scan.1\n",
    "    sudo glassscan man /usr/local/share/man/man1\n",
    "    # Without installing: from a clone, `cargo run --release -- man out/man`.\n",
    "\n",
    exit_status!(),
);

#[cfg(test)]
mod tests {
    use std::path::Path;

    /// The shipped scenes' values that the override flags' help texts quote (`scan --help`:
    /// "40 in edge_study, …") and the defaults quoted for a scene that sets none.
    #[test]
    fn the_defaults_the_flag_help_quotes_are_the_shipped_scenes_values() {
        let load = |name: &str| {
            let path = crate::shipped::resolve_scene(Path::new(name)).unwrap();
            crate::scene::load(&path).unwrap()
        };
        for (name, angle_deg, poses, exposure_ms) in [
            ("edge_study", 40.0, 4, 0.5),
            ("car_side_window", 45.0, 12, 2.0),
            ("flat_opaque", 45.0, 4, 0.015),
        ] {
            let w = load(name);
            assert!(
                (w.scan.scan_angle_rad.to_degrees() - angle_deg).abs() < 1e-9,
                "{name}"
            );
            assert_eq!(w.scan.poses, poses, "{name}");
            assert!(
                (w.sensor.imager.exposure_s * 1e3 - exposure_ms).abs() < 1e-12,
                "{name}"
            );
        }
        let preset = crate::sensor::preset::scancontrol_2600_100();
        assert!((preset.imager.exposure_s - 0.5e-3).abs() < 1e-15);
        for name in crate::shipped::scene_names() {
            let w = load(name);
            assert_eq!(
                w.sensor.firmware.threshold,
                crate::sensor::profile::Threshold::Fixed(128),
                "{name}"
            );
            assert_eq!(
                w.sensor.imager.kind,
                crate::sensor::imager::SensorKind::Cmos,
                "{name}"
            );
        }
    }
}
