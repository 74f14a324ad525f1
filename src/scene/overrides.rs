//! Changes to a scene's method on top of its file: the command line's overrides, and the
//! method variants a scene file lists for the main job ([`super::VariantDef`]).

use super::SceneDef;
use crate::constraint::{JointFlavour, TwistMode};
use crate::ragdoll::SpineKind;
use crate::world::SolverKind;

/// Overrides of a scene file's settings (the command line's, or a variant's); `None` keeps
/// the file's.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    pub iterations: Option<u32>,
    pub substeps: Option<u32>,
    pub solver: Option<SolverKind>,
    pub sleep: Option<bool>,
    pub contact_push_speed: Option<f32>,
    pub contact_warm_start: Option<f32>,
    pub contact_hertz: Option<f32>,
    pub contact_damping_ratio: Option<f32>,
    pub contact_stacking: Option<f32>,
    pub joint_damping: Option<f32>,
    pub dt: Option<f32>,
    pub frames: Option<u32>,
    pub spine: Option<SpineKind>,
    pub joint_flavour: Option<JointFlavour>,
    pub alpha_b: Option<f32>,
    pub alpha_t: Option<f32>,
    /// Rod stiffness in physical units (each replaces its alpha on every rod and rod spine).
    pub bend_stiffness: Option<f32>,
    pub bend_damping: Option<f32>,
    pub twist_stiffness: Option<f32>,
    pub twist_damping: Option<f32>,
    pub twist: Option<TwistMode>,
    /// Record every N-th frame.
    pub record_every: Option<u32>,
}

impl Overrides {
    pub fn apply(&self, def: &mut SceneDef) {
        if let Some(v) = self.iterations {
            def.iterations = v;
        }
        if let Some(v) = self.substeps {
            def.substeps = v;
        }
        if let Some(v) = self.solver {
            def.solver = v;
        }
        if let Some(v) = self.sleep {
            def.sleep = v;
        }
        if let Some(v) = self.contact_push_speed {
            def.contact_push_speed = v;
        }
        if let Some(v) = self.contact_warm_start {
            def.contact_warm_start = v;
        }
        if let Some(v) = self.contact_hertz {
            def.contact_hertz = v;
        }
        if let Some(v) = self.contact_damping_ratio {
            def.contact_damping_ratio = v;
        }
        if let Some(v) = self.contact_stacking {
            def.contact_stacking = v;
        }
        if let Some(v) = self.joint_damping {
            def.joint_damping = v;
        }
        if let Some(v) = self.dt {
            def.dt = v;
        }
        if let Some(v) = self.frames {
            def.frames = v;
        }
        if let Some(v) = self.record_every {
            def.record.every = v;
        }
        if let Some(spine) = self.spine {
            def.ragdoll.iter_mut().for_each(|r| r.spine = spine);
        }
        if let Some(flavour) = self.joint_flavour {
            def.joint_flavour = flavour;
            def.ragdoll
                .iter_mut()
                .for_each(|r| r.joint_flavour = Some(flavour));
            def.joint.iter_mut().for_each(|j| j.flavour = Some(flavour));
        }
        for r in &mut def.ragdoll {
            r.twist = self.twist.or(r.twist);
            let (mut alpha_b, mut alpha_t) = (r.alpha_b, r.alpha_t);
            self.apply_rod(
                &mut alpha_b,
                &mut alpha_t,
                &mut r.bend_stiffness,
                &mut r.bend_damping,
                &mut r.twist_stiffness,
                &mut r.twist_damping,
            );
            (r.alpha_b, r.alpha_t) = (alpha_b, alpha_t);
        }
        for r in &mut def.rod {
            r.twist = self.twist.unwrap_or(r.twist);
            let (mut alpha_b, mut alpha_t) = (Some(r.alpha_b), Some(r.alpha_t));
            self.apply_rod(
                &mut alpha_b,
                &mut alpha_t,
                &mut r.bend_stiffness,
                &mut r.bend_damping,
                &mut r.twist_stiffness,
                &mut r.twist_damping,
            );
            (r.alpha_b, r.alpha_t) = (alpha_b.unwrap_or(0.0), alpha_t.unwrap_or(0.0));
        }
    }

    /// One rod's softness: an alpha given here replaces its stiffness, a stiffness given here
    /// replaces its alpha (`None`: not set).
    fn apply_rod(
        &self,
        alpha_b: &mut Option<f32>,
        alpha_t: &mut Option<f32>,
        bend_stiffness: &mut Option<f32>,
        bend_damping: &mut Option<f32>,
        twist_stiffness: &mut Option<f32>,
        twist_damping: &mut Option<f32>,
    ) {
        let parts = [
            (
                self.alpha_b,
                self.bend_stiffness,
                self.bend_damping,
                alpha_b,
                bend_stiffness,
                bend_damping,
            ),
            (
                self.alpha_t,
                self.twist_stiffness,
                self.twist_damping,
                alpha_t,
                twist_stiffness,
                twist_damping,
            ),
        ];
        for (new_alpha, new_stiffness, new_damping, alpha, stiffness, damping) in parts {
            if new_alpha.is_some() {
                (*alpha, *stiffness, *damping) = (new_alpha, None, None);
            }
            if new_stiffness.is_some() {
                (*alpha, *stiffness) = (None, new_stiffness);
            }
            if new_damping.is_some() {
                *damping = new_damping;
            }
        }
    }

    /// What the overrides cannot do to `def` (after [`Overrides::apply`]): rod settings for a
    /// scene without rods, damping without a stiffness to damp. An error names the flag.
    pub fn check_applied(&self, def: &SceneDef) -> Result<(), String> {
        let rod_spines = || def.ragdoll.iter().filter(|r| r.spine == SpineKind::Rod);
        let has_rods = rod_spines().next().is_some() || !def.rod.is_empty();
        let rod_flags = [
            ("--alpha-b", self.alpha_b.is_some()),
            ("--alpha-t", self.alpha_t.is_some()),
            ("--bend-stiffness", self.bend_stiffness.is_some()),
            ("--twist-stiffness", self.twist_stiffness.is_some()),
            ("--bend-damping", self.bend_damping.is_some()),
            ("--twist-damping", self.twist_damping.is_some()),
        ];
        if let Some((flag, _)) = rod_flags.iter().find(|(_, given)| *given && !has_rods) {
            return Err(format!(
                "{flag}: the scene has no rod (no [[rod]] and no ragdoll with the rod spine; \
                 try --spine rod)"
            ));
        }
        let bend_stiff = rod_spines().any(|r| r.bend_stiffness.is_some())
            || def.rod.iter().any(|r| r.bend_stiffness.is_some());
        let twist_stiff = rod_spines().any(|r| r.twist_stiffness.is_some())
            || def.rod.iter().any(|r| r.twist_stiffness.is_some());
        if self.bend_damping.is_some() && !bend_stiff {
            return Err(
                "--bend-damping damps a bend stiffness, and no rod has one: add --bend-stiffness"
                    .into(),
            );
        }
        if self.twist_damping.is_some() && !twist_stiff {
            return Err("--twist-damping damps a twist stiffness, and no rod has one: add --twist-stiffness".into());
        }
        Ok(())
    }
}
