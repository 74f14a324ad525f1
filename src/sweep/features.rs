//! What modelled features cost: a scene's step timed with and without contacts and joint
//! limits, and its measure with and without the animation-bone mapping.

use std::time::Instant;

use super::median;
use crate::lab::Lab;
use crate::metrics::FrameMetrics;
use crate::scene::Scene;

/// What one modelled feature costs in a scene: the median time with it and without it.
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureCost {
    /// The feature's name.
    pub feature: &'static str,
    /// Whether the scene as written models it.
    pub modelled: bool,
    /// Median microseconds per frame with the feature on and off.
    pub with_us: f64,
    /// Median microseconds per frame with the feature off.
    pub without_us: f64,
}

/// Times the scene's step with and without contacts and joint limits, and the frame's measure
/// with and without the animation-bone mapping (§6), each over `frames` frames. A feature the
/// scene does not model is timed switched on, to show what it would cost. Recording is timed
/// by the caller, which owns the recorder.
pub fn feature_costs(scene: &Scene, frames: u32) -> anyhow::Result<Vec<FeatureCost>> {
    use crate::constraint::Constraint;
    let base = scene.build()?;
    let has_limits = base
        .world
        .constraints
        .iter()
        .any(|c| matches!(c, Constraint::BallSocket(j) if j.limit.is_some()));
    let has_bones = base.ragdolls.iter().any(|r| r.skeleton.is_some());
    let time = |edit: &dyn Fn(&mut Lab), measure: bool| -> anyhow::Result<f64> {
        let mut lab = scene.build()?;
        edit(&mut lab);
        let mut metrics = FrameMetrics::default();
        let mut times = Vec::with_capacity(frames as usize);
        for frame in 0..frames {
            let start = Instant::now();
            if measure {
                metrics.measure(&lab);
            } else {
                lab.step()?;
            }
            if frame >= frames / 10 {
                times.push(start.elapsed().as_secs_f64() * 1e6);
            }
            if measure {
                lab.step()?;
            }
        }
        Ok(median(&mut times))
    };
    let contacts = |on: bool| move |lab: &mut Lab| lab.world.settings.contacts = on;
    let no_limits = |lab: &mut Lab| {
        for c in &mut lab.world.constraints {
            if let Constraint::BallSocket(joint) = c {
                joint.limit = None;
            }
        }
    };
    let no_bones = |lab: &mut Lab| lab.ragdolls.iter_mut().for_each(|r| r.skeleton = None);
    let keep = |_: &mut Lab| {};
    Ok(vec![
        FeatureCost {
            feature: "contacts",
            modelled: base.world.settings.contacts,
            with_us: time(&contacts(true), false)?,
            without_us: time(&contacts(false), false)?,
        },
        FeatureCost {
            feature: "joint limits",
            modelled: has_limits,
            with_us: time(&keep, false)?,
            without_us: time(&no_limits, false)?,
        },
        FeatureCost {
            feature: "bone mapping (measure)",
            modelled: has_bones,
            with_us: time(&keep, true)?,
            without_us: time(&no_bones, true)?,
        },
    ])
}
