//! Changes to a scene's method on top of its file: the command line's overrides, and the
//! method variants a scene file lists for the main job ([`super::VariantDef`]).

use super::SceneDef;
use crate::constraint::{JointFlavour, TwistMode};
use crate::ragdoll::SpineKind;
use crate::world::{ContactDetection, SolverKind};

/// Overrides of a scene file's settings (the command line's, or a variant's); `None` keeps
/// the file's.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// Solver iterations per substep.
    pub iterations: Option<u32>,
    /// Substeps per frame.
    pub substeps: Option<u32>,
    /// How the rows of a colour are solved: scalar or simd.
    pub solver: Option<SolverKind>,
    /// Whether islands of still bodies fall asleep.
    pub sleep: Option<bool>,
    /// Speed limit on pushing out deep overlap (m/s).
    pub contact_push_speed: Option<f32>,
    /// Fraction of their last impulses contacts start each substep with (0 to 1).
    pub contact_warm_start: Option<f32>,
    /// Soft contacts' natural frequency (Hz); 0 is the hard projection.
    pub contact_hertz: Option<f32>,
    /// Soft contacts' damping ratio (1: critical).
    pub contact_damping_ratio: Option<f32>,
    /// Contact mass scaling by height (1/m); 0 is the paper's contact.
    pub contact_stacking: Option<f32>,
    /// When contact points are found: once a frame or every substep.
    pub contact_detection: Option<ContactDetection>,
    /// Angular speed a body's spin is scaled down to each substep (rad/s; inf: none).
    pub angular_speed_limit: Option<f32>,
    /// Rotational dashpot across every joint and rod (N m s/rad).
    pub joint_damping: Option<f32>,
    /// Frame time step (s).
    pub dt: Option<f32>,
    /// Frames to run.
    pub frames: Option<u32>,
    /// Spine of every ragdoll.
    pub spine: Option<SpineKind>,
    /// Flavour of every ball-and-socket joint: the scene's default, every ragdoll's and every
    /// `[[joint]]`'s.
    pub joint_flavour: Option<JointFlavour>,
    /// Bending relaxation alpha_b (eq. 11) of every rod and rod spine; clears their bend
    /// stiffness and damping.
    pub alpha_b: Option<f32>,
    /// Twisting relaxation alpha_t (eq. 12-13) of every rod and rod spine; clears their twist
    /// stiffness and damping.
    pub alpha_t: Option<f32>,
    /// Rod stiffness in physical units (each replaces its alpha on every rod and rod spine).
    pub bend_stiffness: Option<f32>,
    /// Damping of the bend rate (N m s/rad) of every rod and rod spine.
    pub bend_damping: Option<f32>,
    /// Twisting stiffness (N m/rad) of every rod and rod spine; clears their alpha_t.
    pub twist_stiffness: Option<f32>,
    /// Damping of the twist rate (N m s/rad) of every rod and rod spine.
    pub twist_damping: Option<f32>,
    /// Twist measure (exact, or the paper's eq. 12) of every rod and rod spine.
    pub twist: Option<TwistMode>,
    /// Record every N-th frame.
    pub record_every: Option<u32>,
}

impl Overrides {
    /// Writes the overrides that are set into `def`: settings, and spine, flavour and rod settings
    /// on every ragdoll, joint and rod.
    pub fn apply(&self, def: &mut SceneDef) {
        set(&mut def.iterations, self.iterations);
        set(&mut def.substeps, self.substeps);
        set(&mut def.solver, self.solver);
        set(&mut def.sleep, self.sleep);
        set(&mut def.contact_push_speed, self.contact_push_speed);
        set(&mut def.contact_warm_start, self.contact_warm_start);
        set(&mut def.contact_hertz, self.contact_hertz);
        set(&mut def.contact_damping_ratio, self.contact_damping_ratio);
        set(&mut def.contact_stacking, self.contact_stacking);
        set(&mut def.contact_detection, self.contact_detection);
        set(&mut def.angular_speed_limit, self.angular_speed_limit);
        set(&mut def.joint_damping, self.joint_damping);
        set(&mut def.dt, self.dt);
        set(&mut def.frames, self.frames);
        set(&mut def.record.every, self.record_every);
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
        let bend = [self.alpha_b, self.bend_stiffness, self.bend_damping];
        let twist = [self.alpha_t, self.twist_stiffness, self.twist_damping];
        for r in &mut def.ragdoll {
            r.twist = self.twist.or(r.twist);
            soften(
                bend,
                &mut r.alpha_b,
                &mut r.bend_stiffness,
                &mut r.bend_damping,
            );
            soften(
                twist,
                &mut r.alpha_t,
                &mut r.twist_stiffness,
                &mut r.twist_damping,
            );
        }
        for r in &mut def.rod {
            r.twist = self.twist.unwrap_or(r.twist);
            let (mut alpha_b, mut alpha_t) = (Some(r.alpha_b), Some(r.alpha_t));
            soften(
                bend,
                &mut alpha_b,
                &mut r.bend_stiffness,
                &mut r.bend_damping,
            );
            soften(
                twist,
                &mut alpha_t,
                &mut r.twist_stiffness,
                &mut r.twist_damping,
            );
            (r.alpha_b, r.alpha_t) = (alpha_b.unwrap_or(0.0), alpha_t.unwrap_or(0.0));
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

/// One rod part's softness (bend or twist) under the overrides `[alpha, stiffness, damping]`
/// (`None`: not given): an alpha given replaces the stiffness and its damping, a stiffness
/// given replaces the alpha, a damping given replaces the damping.
fn soften(
    [new_alpha, new_stiffness, new_damping]: [Option<f32>; 3],
    alpha: &mut Option<f32>,
    stiffness: &mut Option<f32>,
    damping: &mut Option<f32>,
) {
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

/// Writes `value` into `target` where it is given.
fn set<T>(target: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *target = v;
    }
}
