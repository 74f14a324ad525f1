//! The 30-ragdoll drop (paper Fig. 1, bottom of Fig. 8), by what each file asserts:
//! - `paper`: ten seconds without NaN, nothing through the floor, the piles nearly at rest at
//!   the end, and the rod spine leaving less dislocation than the three-joint spine, as rates
//!   over layouts 1-16 x both spines (the paper's method, the reference line);
//! - `stacking`: stacking's settled residual against the paper's, and the rod below chain3 on
//!   nearly every layout with contacts that carry the pile's weight;
//! - `game`: the pile comes to rest at the game method, as a rate over
//!   layouts 1-128 x both spines;
//! - `landing`: the deepest overlap of the landing within 1 cm, with contacts found every
//!   substep and swept alone after each substep's iterations, as rates over layouts;
//! - `profile`: the step's and detection's profiles account for their time.
//!
//! Helpers the files share are here.

mod game;
mod landing;
mod paper;
mod profile;
mod stacking;

use rodlab::lab::Lab;
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::sim::Overrides;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ragdoll_drop.toml");

/// The drop tests run one at a time: they share rayon's global pool, and a step
/// waiting for the other test's work to leave the pool spends that wait outside every profiled
/// phase (the profile test measured 80% of its stepping time in phases when they overlapped).
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The drop at its `variant` (`None`: the paper's method) with `overrides`: the scene as
/// loaded, and its lab built.
fn drop_lab(variant: Option<&str>, overrides: &Overrides) -> (Scene, Lab) {
    let scene = rodlab::cli::load_scene(SCENE.as_ref(), variant, overrides).unwrap();
    let lab = scene.build().unwrap();
    (scene, lab)
}

fn mean(values: &[f32]) -> f32 {
    values.iter().sum::<f32>() / values.len() as f32
}

/// The runs of a survey over layouts 1-64, both spines.
const SURVEY_RUNS: usize = 128;

/// The scene's `variant` with `overrides` on layouts 1-64 x both spines.
fn survey(variant: &str, overrides: &Overrides) -> Vec<rodlab::sweep::layouts::LayoutRun> {
    survey_over(variant, overrides, 1..=64)
}

/// The scene's `variant` with `overrides` on layouts `seeds` x both spines.
fn survey_over(
    variant: &str,
    overrides: &Overrides,
    seeds: std::ops::RangeInclusive<u64>,
) -> Vec<rodlab::sweep::layouts::LayoutRun> {
    let seeds: Vec<u64> = seeds.collect();
    let spines = [SpineKind::Chain3, SpineKind::Rod];
    let runs = rodlab::sweep::layouts::run_layouts(
        SCENE.as_ref(),
        Some(variant),
        overrides,
        &seeds,
        &spines,
        |_| {},
    )
    .unwrap();
    assert_eq!(runs.len(), 2 * seeds.len());
    runs
}
