//! The paper's drop result at its own method (one step of 20 iterations, cheap joints, hard
//! contacts), the reference line, as rates over layouts 1-16 x both spines: each pile is one
//! sample of a chaotic outcome, so no single layout decides a result.

use super::*;
use rodlab::sweep::layouts::{LayoutEnd, LayoutRun};
use std::sync::OnceLock;

/// The layouts the rates are taken over.
pub(super) const LAYOUTS: std::ops::RangeInclusive<u64> = 1..=16;

/// The drop at its `variant` (`None`: the paper's method) over [`LAYOUTS`] x both spines, 10 s
/// each, every run's end; each variant run once for the whole test binary (`stacking.rs`
/// compares against the paper's).
pub(super) fn layouts(variant: Option<&'static str>) -> &'static [LayoutRun] {
    static PAPER: OnceLock<Vec<LayoutRun>> = OnceLock::new();
    static STACKED: OnceLock<Vec<LayoutRun>> = OnceLock::new();
    let cell = match variant {
        None => &PAPER,
        Some("stacked") => &STACKED,
        Some(other) => panic!("no layouts kept for {other}"),
    };
    cell.get_or_init(|| {
        let _alone = one_at_a_time();
        let seeds: Vec<u64> = LAYOUTS.collect();
        let spines = [SpineKind::Chain3, SpineKind::Rod];
        let runs = rodlab::sweep::layouts::run_layouts(
            SCENE.as_ref(),
            variant,
            &Overrides::default(),
            &seeds,
            &spines,
            |_| {},
        );
        runs.unwrap()
    })
}

/// Each layout's end for `spine`, in seed order; every run must have finished.
pub(super) fn ends(runs: &[LayoutRun], spine: SpineKind) -> Vec<&LayoutEnd> {
    let of = runs.iter().filter(|r| r.spine == spine);
    of.map(|r| match &r.end {
        Ok(end) => end,
        Err(why) => panic!("seed {} {spine}: {why}", r.seed),
    })
    .collect()
}

fn median(mut values: Vec<f32>) -> f32 {
    values.sort_by(f32::total_cmp);
    let n = values.len();
    0.5 * (values[(n - 1) / 2] + values[n / 2])
}

/// Thirty ragdolls fall onto stairs, a ramp and crates and settle, and the rod spine leaves less
/// residual than the three-joint spine (paper Fig. 8, bottom: "a smaller but still
/// consistently positive difference"), over layouts 1-16:
/// - every run finishes its 10 s (no NaN, no explosion) and no body centre goes below the
///   floor (the thinnest limb's radius is 4 cm);
/// - the piles come nearly to rest without sleeping: on the median layout the fastest surface
///   point moves under 1.5 m/s at the end (a few limbs caught between stair boxes and other
///   ragdolls twitch about their long axis);
/// - the rod's mean total dislocation is lower than chain3's on at least 14 of the 16 layouts,
///   and under 0.9 times chain3's on their mean.
#[test]
fn thirty_ragdolls_land_and_settle_and_the_rod_spine_leaves_less_residual() {
    let runs = layouts(None);
    let [chain3, rod] = [SpineKind::Chain3, SpineKind::Rod].map(|s| ends(runs, s));
    for (spine, ends) in [("chain3", &chain3), ("rod", &rod)] {
        let lowest = ends
            .iter()
            .map(|e| e.lowest_centre_m)
            .fold(f32::INFINITY, f32::min);
        let fastest: Vec<f32> = ends
            .iter()
            .map(|e| e.fastest.as_ref().map_or(0.0, |f| f.1))
            .collect();
        let dislocation: Vec<f32> = ends.iter().map(|e| e.mean_dislocation_cm).collect();
        println!(
            "{spine}: lowest centre {lowest:.3} m; fastest point at the end per layout \
             {fastest:.2?} m/s; mean total dislocation per layout {dislocation:.1?} cm"
        );
        assert!(
            lowest > 0.0,
            "{spine}: a body centre reached y = {lowest} m"
        );
        let median_fastest = median(fastest);
        assert!(
            median_fastest < 1.5,
            "{spine}: the median layout's fastest surface point moves at {median_fastest} m/s"
        );
    }
    let lower = (chain3.iter().zip(&rod))
        .filter(|(c, r)| r.mean_dislocation_cm < c.mean_dislocation_cm)
        .count();
    let mean = |ends: &[&LayoutEnd]| {
        ends.iter().map(|e| e.mean_dislocation_cm).sum::<f32>() / ends.len() as f32
    };
    let (chain3_mean, rod_mean) = (mean(&chain3), mean(&rod));
    println!(
        "rod below chain3 on {lower} of {} layouts; mean total dislocation rod {rod_mean:.1} cm, \
         chain3 {chain3_mean:.1} cm ({:.2}x)",
        rod.len(),
        rod_mean / chain3_mean
    );
    assert!(
        lower >= 14,
        "rod below chain3 on only {lower} of 16 layouts"
    );
    assert!(
        rod_mean < 0.9 * chain3_mean,
        "mean total dislocation: rod {rod_mean} cm, chain3 {chain3_mean} cm"
    );
}
