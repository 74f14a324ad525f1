//! Method variants of a scene: `[[variant]]` tables that the main job records beside the
//! scene's own method, e.g. the drop at a game engine's settings next to the paper's.

use super::{Overrides, Scene, SceneDef};
use crate::constraint::JointFlavour;
use crate::world::{ContactDetection, SolverKind};
use serde::Deserialize;

/// One `[[variant]]`: a name and the settings it changes (the rest are the scene's). The main
/// job records the scene once more per variant, as `<scene>_<name>` (per spine, with the
/// spine's name after it); `rodlab run SCENE --variant NAME` runs it alone.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariantDef {
    /// Lower-case letters, digits and underscores; unique in the scene.
    pub name: String,
    /// Solver iterations per substep.
    pub iterations: Option<u32>,
    /// Substeps per frame.
    pub substeps: Option<u32>,
    /// Row solver: scalar or simd.
    pub solver: Option<SolverKind>,
    /// Sleeping of still islands.
    pub sleep: Option<bool>,
    /// Solver flavour of every ball-and-socket joint: cheap or exact.
    pub joint_flavour: Option<JointFlavour>,
    /// Fastest push out of deep contact overlap (m/s).
    pub contact_push_speed: Option<f32>,
    /// Fraction of their last impulses contacts start each substep with (0 to 1).
    pub contact_warm_start: Option<f32>,
    /// Soft contacts' natural frequency (Hz; 0: hard).
    pub contact_hertz: Option<f32>,
    /// Soft contacts' damping ratio.
    pub contact_damping_ratio: Option<f32>,
    /// Stacking rate (1/m; 0: the paper's contact).
    pub contact_stacking: Option<f32>,
    /// When contact points are found: frame (the paper's) or substep.
    pub contact_detection: Option<ContactDetection>,
    /// Angular speed limit (rad/s; inf: none, the paper's).
    pub angular_speed_limit: Option<f32>,
    /// Joint damping (N m s/rad).
    pub joint_damping: Option<f32>,
}

impl VariantDef {
    /// The variant as overrides of the scene file.
    pub fn overrides(&self) -> Overrides {
        Overrides {
            iterations: self.iterations,
            substeps: self.substeps,
            solver: self.solver,
            sleep: self.sleep,
            joint_flavour: self.joint_flavour,
            contact_push_speed: self.contact_push_speed,
            contact_warm_start: self.contact_warm_start,
            contact_hertz: self.contact_hertz,
            contact_damping_ratio: self.contact_damping_ratio,
            contact_stacking: self.contact_stacking,
            contact_detection: self.contact_detection,
            angular_speed_limit: self.angular_speed_limit,
            joint_damping: self.joint_damping,
            ..Default::default()
        }
    }

    /// The scene's settings with this variant applied, for checking.
    pub(super) fn applied_to(&self, def: &SceneDef) -> SceneDef {
        let mut def = def.clone();
        def.variant.clear();
        self.overrides().apply(&mut def);
        def
    }
}

/// A variant name: non-empty, `[a-z0-9_]`, not taken.
pub(super) fn check_variant_name(name: &str, taken: &[&str]) -> Result<(), String> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
    {
        return Err(format!(
            "must be lower-case letters, digits and underscores (it names a recording), got {name:?}"
        ));
    }
    if taken.contains(&name) {
        return Err(format!(
            "a variant named {name:?} comes earlier in this file"
        ));
    }
    Ok(())
}

impl Scene {
    /// The scene at its variant `name`, named `<scene>_<name>`.
    pub fn variant(&self, name: &str) -> anyhow::Result<Scene> {
        let Some(variant) = self.def.variant.iter().find(|v| v.name == name) else {
            let known: Vec<&str> = self.def.variant.iter().map(|v| v.name.as_str()).collect();
            anyhow::bail!(
                "{}: no [[variant]] named {name:?} (the file has {})",
                self.path.display(),
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            );
        };
        let mut scene = self.clone();
        scene.def = variant.applied_to(&self.def);
        scene.def.name = Some(format!("{}_{name}", self.name()));
        Ok(scene)
    }
}
