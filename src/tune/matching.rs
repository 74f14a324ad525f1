//! Matching a bend: the settled psi of one setting, and bisecting alpha_b or the bend
//! stiffness until the settled bend matches a wanted angle (also the chain3 spine's bend, the
//! angle to match).

use anyhow::Context as _;
use rayon::prelude::*;

use super::{
    build_copy, settled, tuned_ragdoll, RodSetting, Softness, Trace, SETTLED_BAND,
    SETTLED_BAND_RAD, SETTLED_WINDOW_S,
};
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::{powf, Vec3};
use crate::ragdoll::SpineKind;
use crate::scene::Scene;

/// The settled psi of the tuned ragdoll with `setting` at `iterations` (no push: the scene's
/// own motion), over the scene's frames or `frames`; `None` if it has not settled
/// ([`settled_value`]).
pub fn settled_psi(
    scene: &Scene,
    setting: RodSetting,
    iterations: u32,
    frames: Option<u32>,
) -> anyhow::Result<Option<f32>> {
    let mut lab = build_copy(scene, setting, iterations, frames, Vec3::ZERO, 0.0)?;
    let frames = frames.unwrap_or(scene.def.frames);
    let mut trace = Trace::default();
    for frame in 1..=frames {
        lab.step()
            .with_context(|| format!("settling at frame {frame}"))?;
        trace.record(&lab);
    }
    Ok(settled_value(&trace.psi, scene.def.dt))
}

/// The mean of `series` over the last [`SETTLED_WINDOW_S`], if it stays within
/// [`SETTLED_BAND`] of it there (or within [`SETTLED_BAND_RAD`], for small values).
pub fn settled_value(series: &[f32], dt: f32) -> Option<f32> {
    let window = ((SETTLED_WINDOW_S / dt).round() as usize).clamp(1, series.len().max(1));
    let value = settled(series, window);
    let band = (SETTLED_BAND * value.abs()).max(SETTLED_BAND_RAD);
    let tail = &series[series.len() - window..];
    tail.iter()
        .all(|x| (x - value).abs() <= band)
        .then_some(value)
}

/// Which setting [`match_psi`] bisects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatchBy {
    /// The relaxation alpha_b (eq. 11).
    AlphaBend,
    /// The bend stiffness (N m/rad), critically damped.
    BendStiffness,
}

/// The upper body's moment of inertia about the rod's first end (kg m^2): the bodies above it,
/// as points plus their own inertia. What the matching's damping is scaled by.
fn bend_inertia(lab: &Lab) -> f32 {
    let world = &lab.world;
    let base = world.constraints.iter().find_map(|c| match c {
        Constraint::Rod(rod) => Some(world.body(rod.body_a).position),
        _ => None,
    });
    let Some(base) = base else { return 0.0 };
    (world.bodies.iter())
        .filter(|b| b.is_dynamic() && b.position.y > base.y)
        .map(|b| b.mass * (b.position - base).length_squared() + b.inertia.max_element())
        .sum()
}

/// The upper body's inertia about the rod's base in the scene (what [`matching_setting`]
/// damps by).
pub fn matching_inertia(scene: &Scene, twist: Softness, iterations: u32) -> anyhow::Result<f32> {
    let plain = matching_setting(MatchBy::AlphaBend, 0.0, twist, 0.0);
    Ok(bend_inertia(&build_copy(
        scene,
        plain,
        iterations,
        None,
        Vec3::ZERO,
        0.0,
    )?))
}

/// The rod setting [`match_psi`] runs for a bend `value`: stiffness critically damped,
/// `c = 2 sqrt(k I)`, with `I` from [`matching_inertia`].
pub fn matching_setting(by: MatchBy, value: f32, twist: Softness, inertia: f32) -> RodSetting {
    let (bend, bend_damping) = match by {
        MatchBy::AlphaBend => (Softness::Alpha(value), None),
        MatchBy::BendStiffness => (
            Softness::Stiffness(value),
            Some(2.0 * (value * inertia).sqrt()),
        ),
    };
    RodSetting {
        bend,
        twist,
        bend_damping,
        twist_damping: None,
    }
}

/// The bend setting whose settled psi is within `tolerance` of `target`: scanned over
/// alpha_b in [1e-6, 1] or the stiffness in [0.1, 1e5] N m/rad (log spaced), then bisected (in
/// log space) between the stiffest neighbours that bracket it. Stiffness runs are
/// critically damped (`c = 2 sqrt(k I)`, `I` the upper body's inertia about the rod's base;
/// damping does not move where they settle) and every run lasts twice the scene's frames.
/// `None` if no setting reaches the target. The twist stays `twist`.
pub fn match_psi(
    scene: &Scene,
    target: f32,
    by: MatchBy,
    twist: Softness,
    iterations: u32,
    tolerance: f32,
) -> anyhow::Result<Option<(f32, f32)>> {
    let frames = Some(matching_frames(scene));
    let inertia = matching_inertia(scene, twist, iterations)?;
    let setting = |value: f32| matching_setting(by, value, twist, inertia);
    // a run still moving at the end counts as no value (NaN)
    let psi_at = |value: f32| {
        settled_psi(scene, setting(value), iterations, frames).map(|p| p.unwrap_or(f32::NAN))
    };
    let (lo, hi) = match by {
        MatchBy::AlphaBend => (1e-6f32, 1.0f32),
        MatchBy::BendStiffness => (0.1, 1e5),
    };
    // A coarse scan first: psi need not fall monotonically as the setting rises (a weak rod
    // swings or tips over), so bisect in the stiffest pair of neighbours that brackets it.
    let scan: Vec<f32> = (0..=MATCH_SCAN)
        .map(|i| lo * powf(hi / lo, i as f32 / MATCH_SCAN as f32))
        .collect();
    let psis = (scan.par_iter())
        .map(|&v| psi_at(v))
        .collect::<anyhow::Result<Vec<f32>>>()?;
    let within = |psi: f32| (psi - target).abs() <= tolerance;
    // the runs that settled, in the order of the setting
    let settled: Vec<(f32, f32)> = (scan.iter().zip(&psis))
        .filter(|(_, psi)| psi.is_finite())
        .map(|(&v, &psi)| (v, psi))
        .collect();
    if let Some(&found) = settled.iter().rev().find(|(_, psi)| within(*psi)) {
        return Ok(Some(found));
    }
    let Some(pair) = (settled.windows(2).rev()).find(|w| w[0].1 > target && w[1].1 < target) else {
        return Ok(None);
    };
    let ((mut lo, _), (mut hi, psi_hi)) = (pair[0], pair[1]);
    let mut best = (hi, psi_hi);
    for _ in 0..40 {
        let mid = (lo * hi).sqrt();
        let psi = psi_at(mid)?;
        if (psi - target).abs() < (best.1 - target).abs() {
            best = (mid, psi);
        }
        if within(psi) {
            break;
        }
        // an unsettled run (NaN) is on the soft side
        if psi > target || psi.is_nan() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(within(best.1).then_some(best))
}

/// Settings [`match_psi`] scans before it bisects, minus one.
const MATCH_SCAN: usize = 12;

/// Frames of every run [`match_psi`] makes: twice the scene's, and at least
/// [`MATCHING_SECONDS`] (the paper's alpha settles slowly: 20 s and more to within 2% in
/// passive bending).
pub fn matching_frames(scene: &Scene) -> u32 {
    (2 * scene.def.frames).max((MATCHING_SECONDS / scene.def.dt).ceil() as u32)
}

/// Shortest run [`match_psi`] makes (s).
pub const MATCHING_SECONDS: f32 = 30.0;

/// How close a match must land (rad): 0.002 rad, or 1% of a smaller target.
pub fn match_tolerance(target: f32) -> f32 {
    (0.01 * target.abs()).clamp(1e-4, 0.002)
}

/// The settled bend of the scene's chain3 spine (its first chain3 ragdoll, else the tuned one
/// with the chain3 spine), measured as the rod would: the angle between the pelvis's and the
/// chest's tangents, the rod's frames taken at the start; `None` if it does not settle.
pub fn chain3_psi(scene: &Scene, iterations: u32) -> anyhow::Result<Option<f32>> {
    let mut scene = scene.clone();
    let def = &mut scene.def;
    let mut ragdoll = match def.ragdoll.iter().find(|r| r.spine == SpineKind::Chain3) {
        Some(r) => r.clone(),
        None => tuned_ragdoll(&scene)?,
    };
    ragdoll.spine = SpineKind::Chain3;
    let name = ragdoll.name.clone();
    scene.def.ragdoll = vec![ragdoll];
    scene.def.iterations = iterations;
    let mut lab = scene.build()?;
    let find = |part: &str| {
        (lab.world.find_body(&format!("{name}/{part}")))
            .with_context(|| format!("the chain3 ragdoll has no {part}"))
    };
    let (pelvis, chest) = (find("pelvis")?, find("chest")?);
    let probe =
        crate::constraint::Rod::instantiate("probe", &lab.world.bodies, pelvis, chest, Vec3::Z)
            .map_err(anyhow::Error::msg)?;
    let mut psi = Vec::new();
    for _ in 0..scene.def.frames {
        lab.step()?;
        psi.push(
            probe
                .state(lab.world.body(pelvis), lab.world.body(chest))
                .psi,
        );
    }
    Ok(settled_value(&psi, scene.def.dt))
}
