//! The sweep's combinations (named methods, spines, joint flavours and the method settings'
//! lists) and the label each method's line gets on the chart.

use super::SweepConfig;
use crate::constraint::BendTwist;
use crate::ragdoll::SpineKind;
use crate::scene::{Method, RodOverrides, SceneDef};
use crate::sim::Overrides;
use crate::solver::METHOD_SETTINGS;
use crate::world::{ContactDetection, Settings};

/// Defines [`SettingLists`]: a list of values for each method setting
/// (`method_settings!` (`solver::settings`)), each a dimension of the sweep.
macro_rules! setting_lists {
    ({} $( $(#[doc = $doc:literal])* $name:ident : $ty:ty = $default:expr,
        unit $unit:literal, bounds $bounds:expr, label $label:literal; )*) => {
        /// The values a sweep runs each method setting at (`rodlab settings` lists them): one
        /// dimension per non-empty list; an empty list keeps the scene's (or the named
        /// method's) value.
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct SettingLists {
            $( $(#[doc = $doc])* pub $name: Vec<$ty>, )*
        }

        impl SettingLists {
            /// Every combination of the lists over each of `base`, in the declared order (the
            /// first setting outermost, `iterations` innermost).
            fn expand(&self, mut all: Vec<Overrides>) -> Vec<Overrides> {
                $( if !self.$name.is_empty() {
                    all = (all.into_iter())
                        .flat_map(|o| self.$name.iter().map(move |v| Overrides {
                            $name: Some(v.clone()),
                            ..o.clone()
                        }))
                        .collect();
                } )*
                all
            }
        }
    };
}
crate::solver::method_settings!(setting_lists! {});

/// The iteration counts a sweep runs when it is given none: solves per frame for named methods.
pub const DEFAULT_ITERATIONS: [u32; 6] = [1, 2, 4, 8, 16, 32];

/// The combinations in run order: method, spine, the rod's bend-twist projection, joint
/// flavour, then the method settings' lists in their declared order (`iterations` last).
pub fn combinations(def: &SceneDef, config: &SweepConfig) -> Vec<Overrides> {
    let mut lists = config.settings.clone();
    if lists.iterations.is_empty() {
        lists.iterations = DEFAULT_ITERATIONS.to_vec();
    }
    let methods: Vec<Option<Method>> = match config.methods.is_empty() {
        true => vec![None],
        false => config.methods.iter().map(|&m| Some(m)).collect(),
    };
    // the rod's bend-twist projection is a rod spine's method dimension only
    let bend_twists = |spine: SpineKind| match (spine, config.bend_twist.is_empty()) {
        (SpineKind::Rod, false) => config.bend_twist.iter().map(|&b| Some(b)).collect(),
        _ => vec![None],
    };
    let mut all = Vec::new();
    for &method in &methods {
        let mut own = def.clone();
        if let Some(method) = method {
            method.overrides().apply(&mut own);
        }
        let joints = match config.joints.is_empty() {
            true => vec![own.joint_flavour],
            false => config.joints.clone(),
        };
        for &spine in &spines(def, &config.spines) {
            for bend_twist in bend_twists(spine) {
                for &joint in &joints {
                    let base = Overrides {
                        method,
                        spine: Some(spine),
                        joint_flavour: Some(joint),
                        frames: config.frames,
                        rod: RodOverrides {
                            bend_twist,
                            ..Default::default()
                        },
                        ..Default::default()
                    };
                    let mut runs = lists.expand(vec![base]);
                    if method.is_some() {
                        // a named method's budget is solves per frame, its iterations per
                        // substep that budget shared by its substeps
                        for o in &mut runs {
                            let substeps = o.substeps.unwrap_or(own.substeps);
                            o.iterations = o.iterations.map(|n| (n / substeps).max(1));
                        }
                        runs.dedup();
                    }
                    // one substep detects once a frame either way: the same method twice
                    let frame_listed = lists.contact_detection.contains(&ContactDetection::Frame);
                    runs.retain(|o| {
                        let substeps = o.substeps.unwrap_or(own.substeps);
                        let detection = o.contact_detection.unwrap_or(own.contact_detection);
                        !(substeps == 1 && detection == ContactDetection::Substep && frame_listed)
                    });
                    all.extend(runs);
                }
            }
        }
    }
    all
}

/// The method's label: `<spine>/<joint>`, then a part for each method setting whose value
/// differs from the paper's (its declared label, e.g. ` simd`, ` x4`, ` soft60Hz`), and
/// ` block` for a rod spine with its bend and twist as one block, so the paper's method keeps
/// its plain name.
pub fn method_label(spine: SpineKind, def: &SceneDef) -> String {
    let mut label = format!("{spine}/{}", def.joint_flavour);
    label += &label_suffixes(spine, def).concat();
    label
}

/// A named method's label: `<spine> <method>`, then the parts of [`method_label`] where the
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

/// The parts of [`method_label`] after `<spine>/<joint>`.
fn label_suffixes(spine: SpineKind, def: &SceneDef) -> Vec<String> {
    let mut settings = Settings::default();
    def.write_method_settings(&mut settings);
    let paper = Settings::default().method_texts();
    let mut label: Vec<String> = (METHOD_SETTINGS.iter())
        .zip(settings.method_texts().into_iter().zip(paper))
        .filter(|(_, ((_, value), (_, reference)))| value != reference)
        .map(|(declared, ((_, value), _))| declared.label_of(&value))
        .filter(|part| !part.is_empty())
        .collect();
    let block = |b: Option<BendTwist>| b == Some(BendTwist::Block);
    if spine == SpineKind::Rod && def.ragdoll.iter().any(|r| block(r.bend_twist)) {
        label.push(" block".into());
    }
    label
}

/// The spines to sweep: those asked for; else the scene's `spines` and single; else its
/// kind's three (chain3 or rig, rod, single).
fn spines(def: &SceneDef, asked: &[SpineKind]) -> Vec<SpineKind> {
    if !asked.is_empty() {
        return asked.to_vec();
    }
    let mut spines = def.default_spines();
    if !spines.contains(&SpineKind::Single) {
        spines.push(SpineKind::Single);
    }
    spines
}
