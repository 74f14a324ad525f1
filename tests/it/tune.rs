//! `rodlab tune`: the grid's recording holds every copy's label and its psi and tau series
//! (read back with Rerun's decoder); stiffer bend rows settle less bent; `--match-psi` lands
//! within 0.01 rad with both kinds of setting; shards 1/3 + 2/3 + 3/3 give exactly the rows of
//! the unsharded run.

use std::collections::BTreeSet;

use crate::common::{decode, frames_with, static_texts, temp_path};
use rodlab::cli::tune::run_grid;
use rodlab::scene::Scene;
use rodlab::tune::{self, MatchBy, Shard, Softness, TuneConfig};

fn passive_bending() -> Scene {
    Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/passive_bending.toml"
    ))
    .unwrap()
}

/// A small grid: 3 bend stiffnesses x 2 twist settings, 2 s.
fn small_grid() -> TuneConfig {
    TuneConfig {
        bend: [50.0, 200.0, 800.0].map(Softness::Stiffness).to_vec(),
        twist: vec![Softness::Alpha(0.5), Softness::Stiffness(100.0)],
        bend_damping: Some(20.0),
        twist_damping: Some(2.0),
        frames: Some(120),
        ..Default::default()
    }
}

#[test]
fn every_copy_of_the_grid_is_labelled_and_has_its_series_in_the_recording() {
    let out = temp_path("tune_grid");
    let scene = passive_bending();
    let config = small_grid();
    let rows = run_grid(&scene, &config, &out).unwrap();
    assert_eq!(rows.len(), 6);
    let chunks = decode(&out.join("tune.rrd"));
    let frames: BTreeSet<i64> = (1..=120).collect();
    for copy in tune::copies(&config, scene.def.iterations) {
        let entity = copy.entity();
        // the label, static, with the copy's settings
        let labels = static_texts(&chunks, &format!("tune/grid/{entity}/label"), "labels");
        assert_eq!(labels, vec![copy.label()], "{entity}");
        for quantity in ["psi", "tau", "energy"] {
            let path = format!("tune/{quantity}/{entity}");
            assert_eq!(frames_with(&chunks, &path, "scalars"), frames, "{path}");
        }
        assert!(
            frames_with(
                &chunks,
                &format!("tune/grid/{entity}/capsules"),
                "translations"
            )
            .len()
                > 100,
            "{entity}: body poses"
        );
    }
    // the CSV and the chart were written beside it
    let csv = std::fs::read_to_string(out.join("tune.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    assert!(out.join("tune.png").exists() && out.join("tune.svg").exists());
}

#[test]
fn stiffer_bend_rows_settle_less_bent() {
    let scene = passive_bending();
    let config = TuneConfig {
        frames: Some(600),
        twist_push: 0.0,
        ..small_grid()
    };
    let (rows, _) = tune::run_grid(&scene, &config, &mut |_, _| Ok(())).unwrap();
    for column in 0..2 {
        let psi: Vec<f32> = (rows.iter())
            .filter(|r| r.copy.column == column)
            .map(|r| r.final_psi)
            .collect();
        println!("column {column}: settled psi by bend stiffness 50, 200, 800: {psi:?}");
        assert!(psi.windows(2).all(|w| w[1] < 0.7 * w[0]), "{psi:?}");
    }
}

#[test]
fn match_psi_lands_within_a_hundredth_of_a_radian_with_alpha_and_with_stiffness() {
    let scene = passive_bending();
    let twist = tune::scene_twist(&scene).unwrap();
    assert_eq!(twist, Softness::Alpha(0.5));
    let target = 0.3;
    let frames = Some(tune::matching_frames(&scene));
    for by in [MatchBy::AlphaBend, MatchBy::BendStiffness] {
        let tolerance = tune::match_tolerance(target);
        let (value, psi) = tune::match_psi(&scene, target, by, twist, 20, tolerance)
            .unwrap()
            .unwrap_or_else(|| panic!("{by:?}: no setting settles at {target}"));
        println!("{by:?}: {value} settles at {psi} rad");
        assert!((psi - target).abs() <= 0.01, "{by:?}: {psi}");
        // the setting found gives the bend again in a fresh run
        let inertia = tune::matching_inertia(&scene, twist, 20).unwrap();
        let setting = tune::matching_setting(by, value, twist, inertia);
        let again = tune::settled_psi(&scene, setting, 20, frames)
            .unwrap()
            .unwrap();
        assert!(
            (again - target).abs() <= 0.01,
            "{by:?}: a fresh run settles at {again}"
        );
    }
}

#[test]
fn three_shards_together_give_exactly_the_rows_of_the_whole_grid() {
    let scene = passive_bending();
    let config = TuneConfig {
        frames: Some(60),
        ..small_grid()
    };
    let (whole, _) = tune::run_grid(&scene, &config, &mut |_, _| Ok(())).unwrap();
    let mut pieces = Vec::new();
    for index in 1..=3 {
        let shard = Shard { index, count: 3 };
        let config = TuneConfig {
            shard,
            ..config.clone()
        };
        let (rows, _) = tune::run_grid(&scene, &config, &mut |_, _| Ok(())).unwrap();
        assert_eq!(rows.len(), 2, "shard {index}/3");
        pieces.extend(rows);
    }
    pieces.sort_by_key(|r| r.copy.index);
    assert_eq!(pieces, whole);
    assert_eq!(tune::to_csv(&pieces), tune::to_csv(&whole));
    // bad shards are refused with the form expected
    for bad in ["0/3", "4/3", "1/0", "x"] {
        let e = bad.parse::<Shard>().unwrap_err();
        assert!(e.contains("I/N"), "{bad}: {e}");
    }
}
