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
    pub joint_damping: Option<f32>,
    pub dt: Option<f32>,
    pub frames: Option<u32>,
    pub spine: Option<SpineKind>,
    pub joint_flavour: Option<JointFlavour>,
    pub alpha_b: Option<f32>,
    pub alpha_t: Option<f32>,
    pub twist: Option<TwistMode>,
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
        if let Some(v) = self.joint_damping {
            def.joint_damping = v;
        }
        if let Some(v) = self.dt {
            def.dt = v;
        }
        if let Some(v) = self.frames {
            def.frames = v;
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
            r.alpha_b = self.alpha_b.or(r.alpha_b);
            r.alpha_t = self.alpha_t.or(r.alpha_t);
            r.twist = self.twist.or(r.twist);
        }
    }
}
