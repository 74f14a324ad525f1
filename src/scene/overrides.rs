//! Changes to a scene's method on top of its file: the command line's overrides, and the
//! method variants (`[[variant]]`) a scene file lists for the main job, read into the same type.

use serde::Deserialize;

use super::locate::{self, Seg};
use super::{Method, Scene, SceneDef};
use crate::constraint::{BendTwist, JointFlavour, TwistMode};
use crate::ragdoll::{SelfContacts, SpineKind};

/// Defines [`Overrides`]: its own fields and every method setting
/// (`method_settings!` (`solver::settings`)) as an optional field.
macro_rules! overrides_struct {
    ({ $( $(#[$fmeta:meta])* $field:ident : $fty:ty, )* }
     $( $(#[doc = $doc:literal])* $name:ident : $ty:ty = $default:expr,
        unit $unit:literal, bounds $bounds:expr, label $label:literal; )*) => {
        /// Overrides of a scene file's settings: the command line's, or a `[[variant]]`'s,
        /// which is read straight into this type; `None` keeps the file's.
        ///
        /// A `[[variant]]` names itself and may set its `method`, any method setting
        /// (`rodlab settings`), `joint_flavour` and `self_contacts`. The fields marked
        /// "command line only" are not read from a scene file, so a variant that sets one is
        /// refused as an unknown field, at its line.
        #[derive(Clone, Debug, Default, PartialEq, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct Overrides {
            $( $(#[$fmeta])* pub $field: $fty, )*
            $( $(#[doc = $doc])* pub $name: Option<$ty>, )*
        }

        impl Overrides {
            /// Writes the method settings that are set into `def`.
            fn apply_method_settings(&self, def: &mut SceneDef) {
                $( set(&mut def.$name, self.$name.clone()); )*
            }

            /// Whether the method setting `key` is set.
            fn sets_method_setting(&self, key: &str) -> bool {
                $( (key == stringify!($name) && self.$name.is_some()) )||*
            }
        }
    };
}

crate::solver::method_settings!(overrides_struct! {
    /// The `[[variant]]`'s name: lower-case letters, digits and underscores, unique in the
    /// scene (it names a recording). `None` for the command line's overrides.
    name: Option<String>,
    /// A named bundle of the method settings ([`Method`]), applied before them: a variant's
    /// own fields, or the command line's flags, win over its method's.
    method: Option<Method>,
    /// Flavour of every ball-and-socket joint: the scene's default, every ragdoll's and every
    /// `[[joint]]`'s.
    joint_flavour: Option<JointFlavour>,
    /// Which pairs of each ragdoll's own bodies may collide ([`SelfContacts`]).
    self_contacts: Option<SelfContacts>,
    /// Frames to run. Command line only.
    #[serde(skip)]
    frames: Option<u32>,
    /// Spine of every ragdoll. Command line only (the main job runs a variant per spine).
    #[serde(skip)]
    spine: Option<SpineKind>,
    /// Softness and twist measure of every rod and rod spine. Command line only.
    #[serde(skip)]
    rod: RodOverrides,
    /// Record every N-th frame. Command line only.
    #[serde(skip)]
    record_every: Option<u32>,
    /// The `[drop]` block's layout seed (each ragdoll's yaw and tip). Command line only.
    #[serde(skip)]
    seed: Option<u64>,
});

/// The command line's settings of every rod and rod spine.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RodOverrides {
    /// Bending: alpha_b (eq. 11), or a stiffness (N m/rad) and the damping of the bend rate.
    pub bend: SoftnessOverride,
    /// Twisting: alpha_t (eq. 12-13), or a stiffness and the damping of the twist rate.
    pub twist: SoftnessOverride,
    /// Twist measure (exact, or the paper's eq. 12).
    pub twist_measure: Option<TwistMode>,
    /// Bend and twist one after the other, or as one block.
    pub bend_twist: Option<BendTwist>,
}

/// One rod part's softness as the command line gives it: an alpha given replaces the file's
/// stiffness and damping, a stiffness given replaces its alpha, a damping given its damping.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftnessOverride {
    /// Relaxation in [0, 1] per iteration (the paper's alpha).
    pub alpha: Option<f32>,
    /// Stiffness (N m/rad), solved in compliance form.
    pub stiffness: Option<f32>,
    /// Damping of the rate (N m s/rad), with a stiffness.
    pub damping: Option<f32>,
}

impl Overrides {
    /// Writes the overrides that are set into `def`: settings, and spine, self-contacts, flavour
    /// and rod settings on every ragdoll, joint and rod.
    pub fn apply(&self, def: &mut SceneDef) {
        if let Some(method) = self.method {
            method.overrides().apply(def);
            def.method = Some(method);
        }
        if let (Some(seed), Some(drop)) = (self.seed, def.drop.as_mut()) {
            // the block's ragdolls were added by name when the file was parsed; only their
            // poses depend on the seed, so what a variant set on them stays
            drop.seed = seed;
            let laid_out: std::collections::HashMap<String, ([f32; 3], [f32; 3])> =
                (drop.placements().into_iter())
                    .map(|(name, position, rotation)| (name, (position, rotation)))
                    .collect();
            for r in &mut def.ragdoll {
                if let Some(&fresh) = laid_out.get(&r.name) {
                    (r.position, r.rotation) = fresh;
                }
            }
            for c in &mut def.character {
                if let Some(&fresh) = laid_out.get(&c.name) {
                    (c.position, c.rotation) = fresh;
                }
            }
        }
        self.apply_method_settings(def);
        set(&mut def.frames, self.frames);
        if let Some(frames) = self.frames {
            // the main job's shorter run cannot be longer than the run
            def.ci_frames = def.ci_frames.map(|n| n.min(frames));
        }
        set(&mut def.record.every, self.record_every);
        if let Some(self_contacts) = self.self_contacts {
            (def.ragdoll.iter_mut()).for_each(|r| r.self_contacts = self_contacts);
        }
        if let Some(spine) = self.spine {
            def.ragdoll.iter_mut().for_each(|r| r.spine = spine);
            def.character.iter_mut().for_each(|c| c.spine = spine);
        }
        if let Some(flavour) = self.joint_flavour {
            def.joint_flavour = flavour;
            def.ragdoll
                .iter_mut()
                .for_each(|r| r.joint_flavour = Some(flavour));
            def.joint.iter_mut().for_each(|j| j.flavour = Some(flavour));
        }
        let RodOverrides {
            bend,
            twist,
            twist_measure,
            bend_twist,
        } = self.rod;
        for r in &mut def.ragdoll {
            r.twist = twist_measure.or(r.twist);
            r.bend_twist = bend_twist.or(r.bend_twist);
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
        for c in &mut def.character {
            c.twist = twist_measure.unwrap_or(c.twist);
            (c.alpha_b, c.alpha_t) = (
                bend.alpha.unwrap_or(c.alpha_b),
                twist.alpha.unwrap_or(c.alpha_t),
            );
        }
        for r in &mut def.rod {
            r.twist = twist_measure.unwrap_or(r.twist);
            r.bend_twist = bend_twist.unwrap_or(r.bend_twist);
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

    /// Checks `scene` after [`Overrides::apply`] against the scene's own rules and bounds
    /// (the very checks its file passed), then [`Overrides::check_applied`]: a setting has one
    /// set of bounds whether the file, a variant or the command line gives it. An error names
    /// the flag that set the field.
    pub fn check_on(&self, scene: &Scene) -> Result<(), String> {
        if let Err((path, message)) = scene.check() {
            return Err(match self.flag_of(&path) {
                Some(flag) => format!("{flag}: {message}"),
                None => format!(
                    "{} (with the command line's settings): {message}",
                    locate::render(&path)
                ),
            });
        }
        self.check_applied(&scene.def)
    }

    /// The flag that set the field at `path`, if the overrides set it.
    fn flag_of(&self, path: &[Seg]) -> Option<String> {
        let Some(Seg::Key(field)) = path.last() else {
            return None;
        };
        if self.sets_method_setting(field) {
            return Some(format!("--{}", field.replace('_', "-")));
        }
        let RodOverrides { bend, twist, .. } = self.rod;
        let flags = [
            ("frames", "--frames", self.frames.is_some()),
            ("spine", "--spine", self.spine.is_some()),
            ("every", "--record-every", self.record_every.is_some()),
            ("alpha_b", "--alpha-b", bend.alpha.is_some()),
            ("alpha_t", "--alpha-t", twist.alpha.is_some()),
            (
                "bend_stiffness",
                "--bend-stiffness",
                bend.stiffness.is_some(),
            ),
            ("bend_damping", "--bend-damping", bend.damping.is_some()),
            (
                "twist_stiffness",
                "--twist-stiffness",
                twist.stiffness.is_some(),
            ),
            ("twist_damping", "--twist-damping", twist.damping.is_some()),
        ];
        (flags.into_iter())
            .find(|(name, _, given)| *given && name == field)
            .map(|(_, flag, _)| flag.to_string())
    }

    /// What the overrides cannot do to `def` (after [`Overrides::apply`]): a seed for a scene
    /// without a `[drop]` block, rod settings for a scene without rods, damping without a
    /// stiffness to damp. An error names the flag.
    pub fn check_applied(&self, def: &SceneDef) -> Result<(), String> {
        if self.seed.is_some() && def.drop.is_none() {
            return Err("--seed lays out a [drop] block's ragdolls, and the scene has none".into());
        }
        let rod_spines = || def.ragdoll.iter().filter(|r| r.spine == SpineKind::Rod);
        let rod_characters = def.character.iter().any(|c| c.spine == SpineKind::Rod);
        let has_rods = rod_spines().next().is_some() || rod_characters || !def.rod.is_empty();
        let RodOverrides { bend, twist, .. } = self.rod;
        let rod_flags = [
            ("--alpha-b", bend.alpha.is_some()),
            ("--alpha-t", twist.alpha.is_some()),
            ("--bend-stiffness", bend.stiffness.is_some()),
            ("--twist-stiffness", twist.stiffness.is_some()),
            ("--bend-damping", bend.damping.is_some()),
            ("--twist-damping", twist.damping.is_some()),
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
        if bend.damping.is_some() && !bend_stiff {
            return Err(
                "--bend-damping damps a bend stiffness, and no rod has one: add --bend-stiffness"
                    .into(),
            );
        }
        if twist.damping.is_some() && !twist_stiff {
            return Err("--twist-damping damps a twist stiffness, and no rod has one: add --twist-stiffness".into());
        }
        Ok(())
    }
}

/// One rod part's softness (bend or twist) under `new` (see [`SoftnessOverride`]).
fn soften(
    new: SoftnessOverride,
    alpha: &mut Option<f32>,
    stiffness: &mut Option<f32>,
    damping: &mut Option<f32>,
) {
    if new.alpha.is_some() {
        (*alpha, *stiffness, *damping) = (new.alpha, None, None);
    }
    if new.stiffness.is_some() {
        (*alpha, *stiffness) = (None, new.stiffness);
    }
    if new.damping.is_some() {
        *damping = new.damping;
    }
}

/// Writes `value` into `target` where it is given.
fn set<T>(target: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *target = v;
    }
}
