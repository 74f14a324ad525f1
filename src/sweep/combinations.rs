//! The sweep's combinations (spine, joint, solver, substeps, contact options, named methods,
//! time step, iterations) and the label each method's line gets on the chart.

use super::SweepConfig;
use crate::constraint::BendTwist;
use crate::ragdoll::SpineKind;
use crate::scene::{Method, RodOverrides, SceneDef};
use crate::sim::Overrides;
use crate::world::{ContactDetection, SolverKind};

/// The combinations in run order: spine, joint, solver, substeps, warm start (these make the
/// method), then time step, then iterations. An empty `substeps`, `solvers` or `warm_starts`
/// list keeps the scene's.
pub fn combinations(def: &SceneDef, config: &SweepConfig) -> Vec<Overrides> {
    if config.methods.is_empty() {
        return combinations_at(def, config, None);
    }
    let at = |method: Method| {
        let mut def = def.clone();
        method.overrides().apply(&mut def);
        combinations_at(&def, config, Some(method))
    };
    config.methods.iter().flat_map(|&m| at(m)).collect()
}

/// [`combinations`] of one method (`None`: the scene's own), an empty list keeping `def`'s.
fn combinations_at(def: &SceneDef, config: &SweepConfig, method: Option<Method>) -> Vec<Overrides> {
    let or_scene = |list: &[f32], scene: f32| match list.is_empty() {
        true => vec![scene],
        false => list.to_vec(),
    };
    let dts = or_scene(&config.dts, def.dt);
    let substeps = match config.substeps.is_empty() {
        true => vec![def.substeps],
        false => config.substeps.clone(),
    };
    let solvers = match config.solvers.is_empty() {
        true => vec![def.solver],
        false => config.solvers.clone(),
    };
    let joints = match config.joints.is_empty() {
        true => vec![def.joint_flavour],
        false => config.joints.clone(),
    };
    let warm_starts = or_scene(&config.warm_starts, def.contact_warm_start);
    let hertz_list = or_scene(&config.contact_hertz, def.contact_hertz);
    let stacking_list = or_scene(&config.contact_stacking, def.contact_stacking);
    let detections = match config.contact_detection.is_empty() {
        true => vec![def.contact_detection],
        false => config.contact_detection.clone(),
    };
    let extra_sweeps = match config.contact_extra_sweeps.is_empty() {
        true => vec![def.contact_extra_sweeps],
        false => config.contact_extra_sweeps.clone(),
    };
    let mut contact_methods = Vec::new();
    for &w in &warm_starts {
        for &f in &hertz_list {
            for &k in &stacking_list {
                for &d in &detections {
                    contact_methods.extend(extra_sweeps.iter().map(|&n| (w, f, k, d, n)));
                }
            }
        }
    }
    // the rod's bend-twist projection is a rod spine's method dimension only
    let bend_twists = |spine: SpineKind| match (spine, config.bend_twist.is_empty()) {
        (SpineKind::Rod, false) => config.bend_twist.iter().map(|&b| Some(b)).collect(),
        _ => vec![None],
    };
    let mut all = Vec::new();
    for &spine in &config.spines {
        for bend_twist in bend_twists(spine) {
            for &joint in &joints {
                for &solver in &solvers {
                    for &substeps in &substeps {
                        for &(warm, hertz, stacking, detection, sweeps) in &contact_methods {
                            // one substep detects once a frame either way: the same method twice
                            let frame_listed = detections.contains(&ContactDetection::Frame);
                            if substeps == 1
                                && detection == ContactDetection::Substep
                                && frame_listed
                            {
                                continue;
                            }
                            // a named method's budget is solves per frame, its iterations
                            // per substep that budget shared by its substeps
                            let mut iteration_counts: Vec<u32> = match method {
                                None => config.iterations.clone(),
                                Some(_) => (config.iterations.iter())
                                    .map(|&n| (n / substeps).max(1))
                                    .collect(),
                            };
                            iteration_counts.dedup();
                            for &dt in &dts {
                                for &iterations in &iteration_counts {
                                    all.push(Overrides {
                                        method,
                                        spine: Some(spine),
                                        joint_flavour: Some(joint),
                                        solver: Some(solver),
                                        substeps: Some(substeps),
                                        contact_warm_start: Some(warm),
                                        contact_hertz: Some(hertz),
                                        contact_stacking: Some(stacking),
                                        contact_detection: Some(detection),
                                        contact_extra_sweeps: Some(sweeps),
                                        dt: Some(dt),
                                        iterations: Some(iterations),
                                        frames: config.frames,
                                        rod: RodOverrides {
                                            bend_twist,
                                            ..Default::default()
                                        },
                                        ..Default::default()
                                    });
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    all
}

/// The method's label: `<spine>/<joint>`, then ` simd` unless scalar, ` x<substeps>` unless
/// 1, ` warm<w>`, ` soft<f>Hz` and ` stack<k>` unless 0, ` redetect` with detection every
/// substep, ` sweeps<n>` with extra contact sweeps, and ` block` for a rod spine with its bend
/// and twist as one block (so the paper's method keeps its plain name); the joint flavour,
/// solver, substeps
/// and contact settings are the scene's.
pub fn method_label(spine: SpineKind, def: &SceneDef) -> String {
    let mut label = format!("{spine}/{}", def.joint_flavour);
    label += &label_suffixes(spine, def).concat();
    label
}

/// A named method's label: `<spine> <method>`, then the suffixes of [`method_label`] where the
/// run's settings differ from the method's own (a dimension swept across the methods).
pub fn named_method_label(method: Method, spine: SpineKind, def: &SceneDef) -> String {
    let mut own = def.clone();
    method.overrides().apply(&mut own);
    let mut label = format!("{spine} {method}");
    if def.joint_flavour != own.joint_flavour {
        label += &format!(" {}", def.joint_flavour);
    }
    let own = label_suffixes(spine, &own);
    for suffix in label_suffixes(spine, def) {
        if !own.contains(&suffix) {
            label += &suffix;
        }
    }
    label
}

/// The suffixes of [`method_label`] after `<spine>/<joint>`.
fn label_suffixes(spine: SpineKind, def: &SceneDef) -> Vec<String> {
    let mut label = Vec::new();
    if def.solver != SolverKind::Scalar {
        label.push(format!(" {}", def.solver));
    }
    if def.substeps != 1 {
        label.push(format!(" x{}", def.substeps));
    }
    if def.contact_warm_start != 0.0 {
        label.push(format!(" warm{}", def.contact_warm_start));
    }
    if def.contact_hertz != 0.0 {
        label.push(format!(" soft{}Hz", def.contact_hertz));
    }
    if def.contact_stacking != 0.0 {
        label.push(format!(" stack{}", def.contact_stacking));
        if def.contact_stacking_max_ratio.is_finite() {
            label.push(format!("<={}", def.contact_stacking_max_ratio));
        }
    }
    if def.contact_detection != ContactDetection::Frame {
        label.push(" redetect".into());
    }
    if def.contact_extra_sweeps != 0 {
        label.push(format!(" sweeps{}", def.contact_extra_sweeps));
    }
    let block = |b: Option<BendTwist>| b == Some(BendTwist::Block);
    if spine == SpineKind::Rod && def.ragdoll.iter().any(|r| block(r.bend_twist)) {
        label.push(" block".into());
    }
    if def.joint_damping > 0.0 {
        label.push(format!(" jd{}", def.joint_damping));
    }
    if def.joint_friction > 0.0 {
        label.push(format!(" jf{}", def.joint_friction));
    }
    label
}
