//! The sweep: residual falls as iterations rise for every method, in the passive-bending scene
//! and in a short drop with contacts; the CSV columns are documented and read back.

use rodlab::constraint::JointFlavour;
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::sweep::{self, SettingLists, SweepConfig, SweepRow};

const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");

fn run(scene: &str, config: &SweepConfig) -> Vec<SweepRow> {
    let scene = Scene::load(format!("{SCENES}/{scene}.toml")).unwrap();
    sweep::combinations(&scene.def, config)
        .iter()
        .map(|o| sweep::run_one(&scene, o, config.repeats).unwrap())
        .collect()
}

/// For each method, the mean dislocation at each iteration count is below the one before.
fn assert_falls_with_iterations(rows: &[SweepRow], ratio: f64) {
    let mut methods: Vec<&str> = rows.iter().map(|r| r.method.as_str()).collect();
    methods.dedup();
    for method in methods {
        let line: Vec<&SweepRow> = rows.iter().filter(|r| r.method == method).collect();
        for pair in line.windows(2) {
            assert!(pair[0].failed.is_none() && pair[1].failed.is_none());
            assert!(
                pair[1].mean_dislocation_cm < pair[0].mean_dislocation_cm,
                "{method}: {} cm at {} iterations, {} cm at {}",
                pair[1].mean_dislocation_cm,
                pair[1].settings.iterations,
                pair[0].mean_dislocation_cm,
                pair[0].settings.iterations
            );
        }
        let (first, last) = (line[0], line[line.len() - 1]);
        assert!(
            last.mean_dislocation_cm < ratio * first.mean_dislocation_cm,
            "{method}: only from {} to {} cm",
            first.mean_dislocation_cm,
            last.mean_dislocation_cm
        );
    }
}

#[test]
fn residual_falls_as_iterations_rise_for_every_method() {
    let rows = run(
        "passive_bending",
        &SweepConfig {
            repeats: 1,
            ..Default::default()
        },
    );
    assert_eq!(rows.len(), 36);
    // measured: from 1 to 32 iterations the residual falls 25x (chain3) to 430x (rod/cheap)
    assert_falls_with_iterations(&rows, 0.1);
}

#[test]
fn residual_falls_as_iterations_rise_in_a_short_drop_with_contacts() {
    let rows = run(
        "ragdoll_drop",
        &SweepConfig {
            settings: SettingLists {
                iterations: vec![2, 8, 32],
                ..Default::default()
            },
            spines: vec![SpineKind::Chain3, SpineKind::Rod],
            joints: vec![JointFlavour::Exact],
            frames: Some(120),
            repeats: 1,
            ..Default::default()
        },
    );
    assert_falls_with_iterations(&rows, 0.5);
    // the pile lands within the 120 frames: every run reports a real overlap (found afresh), and
    // it reads back from the CSV
    assert!(
        rows.iter()
            .all(|r| r.max_overlap_cm > 0.1 && r.max_overlap_cm < 50.0),
        "{:?}",
        rows.iter().map(|r| r.max_overlap_cm).collect::<Vec<_>>()
    );
    let back = sweep::parse_csv(&sweep::to_csv(&rows)).unwrap();
    for (a, b) in rows.iter().zip(&back) {
        assert!((a.max_overlap_cm - b.max_overlap_cm).abs() < 1e-3);
    }
}

#[test]
fn csv_columns_are_documented_and_read_back() {
    let rows = run(
        "passive_bending",
        &SweepConfig {
            settings: SettingLists {
                iterations: vec![1, 4],
                ..Default::default()
            },
            spines: vec![SpineKind::Rod],
            frames: Some(20),
            repeats: 1,
            ..Default::default()
        },
    );
    let csv = sweep::to_csv(&rows);
    let header = csv.lines().next().unwrap();
    let docs =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/sweep.rs")).unwrap();
    // the method settings' columns are the declared settings, in order; the others are
    // listed in the module's table
    let settings: Vec<&str> = rodlab::solver::METHOD_SETTINGS
        .iter()
        .map(|d| d.name)
        .collect();
    let columns: Vec<&str> = header.split(',').collect();
    assert_eq!(columns[3..3 + settings.len()], settings[..]);
    for column in columns[..3].iter().chain(&columns[3 + settings.len()..]) {
        assert!(
            docs.contains(&format!("`{column}`")),
            "column {column} is not in the module's table of columns"
        );
    }
    let back = sweep::parse_csv(&csv).unwrap();
    assert_eq!(back.len(), rows.len());
    for (a, b) in rows.iter().zip(&back) {
        assert_eq!(
            (&a.method, &a.spine, &a.joint, a.settings.iterations),
            (&b.method, &b.spine, &b.joint, b.settings.iterations)
        );
        assert!((a.settings.dt - b.settings.dt).abs() < 1e-7);
        assert!((a.step_us - b.step_us).abs() < 1e-3);
        assert!((a.mean_dislocation_cm - b.mean_dislocation_cm).abs() < 1e-6);
        assert!((a.max_angular_rad - b.max_angular_rad).abs() < 1e-6);
    }
    // a broken number is reported with its line and column
    let broken = csv.replacen("0.016666668,1,", "0.016666668,x,", 1);
    let error = sweep::parse_csv(&broken).unwrap_err().to_string();
    assert!(
        error.contains("line 2") && error.contains("iterations"),
        "{error}"
    );
}

/// A scene without contacts does no collision work at all: the contact storage is never
/// touched. The same scene with contacts on does fill it, so the check can fail.
#[test]
fn a_scene_without_contacts_pays_nothing_for_collision_detection() {
    let scene = Scene::load(format!("{SCENES}/passive_bending.toml")).unwrap();
    assert!(!scene.def.contacts);
    for contacts in [false, true] {
        let mut world = scene.build().unwrap().world;
        world.settings.contacts = contacts;
        for _ in 0..60 {
            world.step().unwrap();
        }
        let touched = world.contacts.points.capacity() > 0;
        assert_eq!(touched, contacts, "contacts = {contacts}");
    }
    let costs = sweep::feature_costs(&scene, 20).unwrap();
    let names: Vec<(&str, bool)> = costs.iter().map(|c| (c.feature, c.modelled)).collect();
    assert_eq!(
        names,
        [
            ("contacts", false),
            ("joint limits", true),
            ("bone mapping (measure)", true)
        ]
    );
    assert!(costs.iter().all(|c| c.with_us > 0.0 && c.without_us > 0.0));
}

/// `rodlab sweep --shard I/N`, run as a user runs it: the three shards' CSV rows together are
/// exactly the unsharded run's, up to the measured step time (column 10), and each shard wrote
/// its own files; `rodlab merge` puts them back in the whole run's order.
#[test]
fn three_sweep_shards_together_give_exactly_the_rows_of_the_whole_sweep() {
    let out = std::env::temp_dir().join(format!("rodlab-sweep-shards-{}", std::process::id()));
    let sweep = |shard: Option<&str>| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"));
        command.args(["sweep", &format!("{SCENES}/passive_bending.toml")]);
        command.args([
            "--spines",
            "chain3,rod",
            "--joint",
            "cheap",
            "--iterations",
            "1,2,4",
        ]);
        command
            .args(["--frames", "20", "--repeats", "1", "--out"])
            .arg(&out);
        if let Some(shard) = shard {
            command.args(["--shard", shard]);
        }
        let status = command.status().unwrap();
        assert!(status.success(), "{shard:?}");
        let name = match shard {
            None => "passive_bending_sweep.csv".to_string(),
            Some(s) => format!("passive_bending_sweep_shard{}.csv", s.replace('/', "of")),
        };
        rows_but_time(&out.join(name))
    };
    let whole = sweep(None);
    assert_eq!(whole.len(), 6);
    let mut pieces: Vec<String> = ["1/3", "2/3", "3/3"]
        .iter()
        .flat_map(|s| {
            let rows = sweep(Some(s));
            assert_eq!(rows.len(), 2, "shard {s}");
            rows
        })
        .collect();
    let mut sorted = whole.clone();
    sorted.sort();
    pieces.sort();
    assert_eq!(pieces, sorted);
    // `rodlab merge` puts them back in the whole run's order, and writes its chart and recording
    let merged = out.join("merged");
    let shards =
        ["3of3", "1of3", "2of3"].map(|s| out.join(format!("passive_bending_sweep_shard{s}.csv")));
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"))
        .arg("merge")
        .args(&shards)
        .arg("--out")
        .arg(&merged)
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(
        rows_but_time(&merged.join("passive_bending_sweep.csv")),
        whole
    );
    for ext in ["svg", "png", "rrd"] {
        assert!(
            merged.join(format!("passive_bending_sweep.{ext}")).exists(),
            "{ext}"
        );
    }
    // two of three shards are refused, naming what is missing
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"))
        .arg("merge")
        .args(&shards[..2])
        .output()
        .unwrap();
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && message.contains("each of 1 to 3 of 3"),
        "{message}"
    );
}

/// A sweep CSV's rows, every column but the step time joined by `|`, read as CSV (a failure
/// message may hold commas).
fn rows_but_time(csv: &std::path::Path) -> Vec<String> {
    let csv = std::fs::read_to_string(csv).unwrap();
    let header = csv.lines().next().unwrap();
    let step_us = header.split(',').position(|c| c == "step_us").unwrap();
    (rodlab::csv_table::read(&csv, header).unwrap().iter())
        .map(|(_, record)| {
            let mut fields: Vec<&str> = record.iter().collect();
            fields.remove(step_us);
            fields.join("|")
        })
        .collect()
}

/// A failure message holding commas, quotes and a newline survives the CSV whole (it used to
/// have its commas replaced).
#[test]
fn a_failure_message_with_commas_reads_back_whole() {
    let mut rows = run(
        "passive_bending",
        &SweepConfig {
            settings: SettingLists {
                iterations: vec![1],
                ..Default::default()
            },
            spines: vec![SpineKind::Rod],
            frames: Some(5),
            repeats: 1,
            ..Default::default()
        },
    );
    let message = "frame 3: body \"drop1/head\", constraint \"neck\", NaN,\nstopped";
    rows[0].failed = Some(message.to_string());
    let back = sweep::parse_csv(&sweep::to_csv(&rows)).unwrap();
    assert_eq!(back[0].failed.as_deref(), Some(message));
    assert_eq!(back[0].method, rows[0].method);
}

/// `contact_extra_sweeps` is a sweep dimension: each count is a method of its own, labelled
/// ` sweeps<n>` (none for 0, the paper's), with its own CSV column read back; and the sweeps
/// reach the solver (the drop's landing, 10 substeps of one iteration with contacts found
/// every substep, leaves a different pile with three of them).
#[test]
fn extra_contact_sweeps_are_a_sweep_dimension() {
    let config = SweepConfig {
        settings: SettingLists {
            iterations: vec![1],
            substeps: vec![10],
            contact_detection: vec![rodlab::world::ContactDetection::Substep],
            contact_extra_sweeps: vec![0, 3],
            ..Default::default()
        },
        spines: vec![SpineKind::Rod],
        joints: vec![JointFlavour::Cheap],
        frames: Some(90),
        repeats: 1,
        ..Default::default()
    };
    let rows = run("ragdoll_drop", &config);
    let labels: Vec<(&str, u32)> = (rows.iter())
        .map(|r| (r.method.as_str(), r.settings.contact_extra_sweeps))
        .collect();
    assert_eq!(
        labels,
        [
            ("rod/cheap x10 redetect", 0),
            ("rod/cheap x10 redetect sweeps3", 3)
        ]
    );
    assert!(rows.iter().all(|r| r.failed.is_none()));
    assert_ne!(
        (rows[0].mean_dislocation_cm, rows[0].max_overlap_cm),
        (rows[1].mean_dislocation_cm, rows[1].max_overlap_cm)
    );
    let back = sweep::parse_csv(&sweep::to_csv(&rows)).unwrap();
    assert_eq!(back[1].settings.contact_extra_sweeps, 3);
}

/// Named methods are lines of their own at the same budget: with `--methods`, `iterations`
/// counts solves per frame, which each method shares over its own substeps; each line is
/// labelled `<spine> <method>`, and a list given beside the methods overrides that field in
/// every method and shows in the label.
#[test]
fn named_methods_are_lines_at_the_same_budget() {
    use rodlab::scene::Method;
    let scene = Scene::load(format!("{SCENES}/ragdoll_drop.toml")).unwrap();
    let config = SweepConfig {
        settings: SettingLists {
            iterations: vec![4, 20, 40],
            ..Default::default()
        },
        methods: Method::ALL.to_vec(),
        spines: vec![SpineKind::Rod],
        joints: Vec::new(),
        frames: Some(2),
        repeats: 1,
        ..Default::default()
    };
    // each method keeps its own substeps (unset), its iterations the budget shared by them
    let runs: Vec<(Option<Method>, Option<u32>, Option<u32>)> =
        (sweep::combinations(&scene.def, &config).iter())
            .map(|o| (o.method, o.substeps, o.iterations))
            .collect();
    let (paper, game, tight) = (Some(Method::Paper), Some(Method::Game), Some(Method::Tight));
    #[rustfmt::skip]
    assert_eq!(runs, [
        (paper, None, Some(4)), (paper, None, Some(20)), (paper, None, Some(40)),
        (game, None, Some(1)), (game, None, Some(5)), (game, None, Some(10)),
        (tight, None, Some(1)), (tight, None, Some(2)),
    ]);
    let labels = |config: &SweepConfig| -> Vec<String> {
        let mut labels: Vec<String> = (sweep::combinations(&scene.def, config).iter())
            .map(|o| sweep::run_one(&scene, o, 1).unwrap().method)
            .collect();
        labels.dedup();
        labels
    };
    let one_budget = SweepConfig {
        settings: SettingLists {
            iterations: vec![20],
            ..Default::default()
        },
        ..config.clone()
    };
    assert_eq!(labels(&one_budget), ["rod paper", "rod game", "rod tight"]);
    let cheap = SweepConfig {
        joints: vec![JointFlavour::Cheap],
        ..one_budget
    };
    assert_eq!(
        labels(&cheap),
        ["rod paper", "rod game cheap", "rod tight cheap"]
    );
}

/// The rod's bend-twist projection is a method dimension of the rod spine only: with both
/// listed, chain3 runs once and the rod twice, the block line labelled ` block` beside the
/// reference, and each line's residual falls with iterations; at 16 iterations the block
/// leaves the rod's residual within 20% of the sequential one.
#[test]
fn the_rod_bend_twist_block_is_a_line_beside_the_reference() {
    use rodlab::constraint::BendTwist;
    let rows = run(
        "passive_bending",
        &SweepConfig {
            settings: SettingLists {
                iterations: vec![4, 16],
                ..Default::default()
            },
            spines: vec![SpineKind::Chain3, SpineKind::Rod],
            joints: vec![JointFlavour::Cheap],
            bend_twist: vec![BendTwist::Sequential, BendTwist::Block],
            repeats: 1,
            ..Default::default()
        },
    );
    let methods: Vec<&str> = rows.iter().map(|r| r.method.as_str()).collect();
    assert_eq!(
        methods,
        [
            "chain3/cheap",
            "chain3/cheap",
            "rod/cheap",
            "rod/cheap",
            "rod/cheap block",
            "rod/cheap block"
        ]
    );
    assert_falls_with_iterations(&rows, 0.5);
    let (sequential, block) = (&rows[3], &rows[5]);
    let ratio = block.mean_dislocation_cm / sequential.mean_dislocation_cm;
    assert!(
        (ratio - 1.0).abs() < 0.2,
        "block {} cm against sequential {} cm at 16 iterations",
        block.mean_dislocation_cm,
        sequential.mean_dislocation_cm
    );
}

/// `rodlab layouts`: each run is the drop at that seed and spine, exactly as a run of it alone
/// (the same deepest overlap and dislocation to the bit, whatever the thread count), in the
/// order of the seeds; the seeds parse as numbers and ranges; a scene without a `[drop]`
/// block, or overrides that set the seed, are refused.
#[test]
fn layouts_are_the_drop_run_at_each_seed_in_order() {
    use clap::Parser as _;
    use rodlab::cli::{Cli, Command};
    use rodlab::sim::{self, Overrides};
    use rodlab::sweep::layouts::{layouts_csv, run_layouts, LAYOUTS_HEADER};
    let cli = Cli::try_parse_from(["rodlab", "layouts", "x.toml", "--seeds", "4-6,2"]).unwrap();
    let Some(Command::Layouts(args)) = cli.command else {
        panic!("not the layouts command");
    };
    assert_eq!(args.seeds.0, [4, 5, 6, 2]);
    for bad in ["6-4", "x", "1-", "3,,4"] {
        let parsed = Cli::try_parse_from(["rodlab", "layouts", "x.toml", "--seeds", bad]);
        assert!(parsed.is_err(), "--seeds {bad}");
    }

    let scene = format!("{SCENES}/ragdoll_drop.toml");
    let frames = Overrides {
        frames: Some(40),
        ..Default::default()
    };
    let mut seen = 0;
    let runs = run_layouts(
        scene.as_ref(),
        Some("game"),
        &frames,
        &[3, 1],
        &[SpineKind::Rod],
        |_| seen += 1,
    )
    .unwrap();
    assert_eq!(seen, 2);
    let order: Vec<u64> = runs.iter().map(|r| r.seed).collect();
    assert_eq!(order, [3, 1]);
    for run in &runs {
        let end = run.end.as_ref().unwrap();
        let mut alone = Scene::load(&scene).unwrap().variant("game").unwrap();
        Overrides {
            seed: Some(run.seed),
            spine: Some(SpineKind::Rod),
            frames: Some(40),
            ..Default::default()
        }
        .apply(&mut alone.def);
        let mut lab = alone.build().unwrap();
        let report = sim::run(&mut lab, 40, &mut sim::NoObserver).unwrap();
        let mean = report.total_dislocation_cm.iter().sum::<f32>() / 40.0;
        assert_eq!(
            end.deepest_overlap_cm, report.max_overlap_cm,
            "seed {}",
            run.seed
        );
        assert_eq!(end.mean_dislocation_cm, mean, "seed {}", run.seed);
        let at_rest = 1000.0 * lab.world.overlap_at_rest().2;
        assert_eq!(end.overlap_at_rest_mm, at_rest, "seed {}", run.seed);
        // at 40 frames the pile is still landing
        assert!(end.still_moving > 0 && end.all_asleep_from.is_none());
    }
    assert_ne!(runs[0].end, runs[1].end, "two seeds, one pile");
    let csv = layouts_csv(&runs);
    assert!(csv.starts_with(LAYOUTS_HEADER));
    assert_eq!(csv.lines().count(), 3);

    let no_drop = format!("{SCENES}/passive_bending.toml");
    let e = run_layouts(
        no_drop.as_ref(),
        None,
        &frames,
        &[1],
        &[SpineKind::Rod],
        |_| {},
    );
    assert!(format!("{:#}", e.unwrap_err()).contains("has no [drop] block"));
    let seeded = Overrides {
        seed: Some(2),
        ..Default::default()
    };
    let e = run_layouts(
        scene.as_ref(),
        None,
        &seeded,
        &[1],
        &[SpineKind::Rod],
        |_| {},
    );
    assert!(e.is_err());
}
