//! Named methods: `method = "paper" | "game" | "tight"` in a scene, in a `[[variant]]` and as
//! `--method`, each a bundle of solver and contact settings written once below, as a scene
//! file would write them. Single fields stay overridable: a scene's own keys win over its
//! `method`, a variant's over its `method`, the command line's flags over `--method`.
//!
//! | method | what it is for |
//! |---|---|
//! | `paper` | the paper's method (§4): one step of 20 sequential iterations, the cheap joint, hard contacts; the reference line on every chart |
//! | `game` | what a game ships: piles come to rest and sleep, stacks stand, overlap is pushed out gently (4 substeps of 4 iterations, soft and warm-started contacts, joint damping and friction, sleeping) |
//! | `tight` | low error for the paper's budget of 20 solves a frame (20 substeps of one iteration, contacts found every substep and swept last, stacking, overlap pushed out at most 5 m/s) |
//!
//! What each choice buys is measured in docs/contacts.md, docs/landings.md and docs/rest.md;
//! `rodlab methods` prints the bundles.

use serde::Deserialize;

use super::{Overrides, SceneDef};
use crate::solver::METHOD_SETTINGS;
use crate::world::Settings;

/// A named bundle of method settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// The paper's method and the reference.
    Paper,
    /// A game engine's settings: at rest, asleep, gentle.
    Game,
    /// Low error for the paper's budget.
    Tight,
}

impl Method {
    /// Every method, the reference first.
    pub const ALL: [Method; 3] = [Method::Paper, Method::Game, Method::Tight];

    /// The bundle as a scene file writes it: every method field each method decides, so that a
    /// method applied over another leaves nothing of it.
    pub fn settings_toml(self) -> &'static str {
        match self {
            Method::Paper => PAPER,
            Method::Game => GAME,
            Method::Tight => TIGHT,
        }
    }

    /// The bundle as overrides ([`Method::settings_toml`] read as a `[[variant]]`).
    pub fn overrides(self) -> Overrides {
        toml::from_str(self.settings_toml()).expect("a method's settings are valid overrides")
    }

    /// The bundle without the `keys` a scene file sets itself (a scene's own keys win).
    pub(super) fn overrides_under(self, keys: &[String]) -> Overrides {
        let mut preset: toml::Table =
            toml::from_str(self.settings_toml()).expect("a method's settings are a table");
        preset.retain(|key, _| !keys.iter().any(|k| k == key));
        preset
            .try_into()
            .expect("a method's settings are valid overrides")
    }
}

/// The method settings as a Markdown table (`rodlab settings`, docs/scene-format.md): each
/// one's key, unit, values, its value in each named method, and what it does.
pub fn settings_table() -> String {
    let values: Vec<Vec<(&str, String)>> = (Method::ALL.iter())
        .map(|m| {
            let mut def: SceneDef = toml::from_str("").expect("an empty scene is valid");
            m.overrides().apply(&mut def);
            let mut settings = Settings::default();
            def.write_method_settings(&mut settings);
            settings.method_texts()
        })
        .collect();
    let mut table = String::from("| setting | unit | values |");
    for method in Method::ALL {
        table += &format!(" `{method}` |");
    }
    table += " what it does |\n|---|---|---|";
    table += &"---|".repeat(Method::ALL.len() + 1);
    for (i, declared) in METHOD_SETTINGS.iter().enumerate() {
        let doc: Vec<&str> = declared.doc.lines().map(str::trim).collect();
        table += &format!(
            "\n| `{}` | {} | {} |",
            declared.name,
            declared.unit,
            (declared.values)().replace(&format!(" ({})", declared.unit), "")
        );
        for method in &values {
            table += &format!(" {} |", method[i].1);
        }
        table += &format!(" {} |", doc.join(" "));
    }
    table + "\n"
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Paper => "paper",
            Method::Game => "game",
            Method::Tight => "tight",
        })
    }
}

/// The paper's method (§4, §7): one step of 20 Gauss-Seidel iterations over the rows in their
/// stored order, the cheap joint, contacts projected hard, nothing carried between frames.
const PAPER: &str = r#"
solver = "scalar"
substeps = 1
iterations = 20
joint_flavour = "cheap"
contact_push_speed = inf
contact_extra_sweeps = 0
contact_warm_start = 0.0
contact_hertz = 0.0
contact_damping_ratio = 1.0
contact_stacking = 0.0
contact_stacking_max_ratio = inf
contact_detection = "frame"
joint_damping = 0.0
joint_friction = 0.0
sleep = false
"#;

/// A game engine's settings. Over the drop's layouts 1-128 x both spines, all 256 piles are
/// at rest after 10 s (docs/rest.md, The drop at rest):
/// - 4 substeps of 4 iterations, SIMD, exact joints (hinges as one 2x2 block);
/// - contacts warm-started with their whole last impulse and soft at 90 Hz: a soft contact
///   sags `g / omega^2` per unit of the load it carries over its own pair's weight, 6.9 mm at
///   the top of a ten-box stack at 60 Hz and 3.1 mm at 90 Hz; warm-started with a quarter of
///   the impulse the stack also leans 1.3 cm in its first second, with all of it 1 mm;
/// - overlap pushed out at no more than 3 m/s (Box2D's cap; Unity's is 10): a limb trapped in
///   its own ragdoll's chest otherwise pumps the push-out into the ragdoll;
/// - a joint dashpot (0.2 N m s/rad) and Coulomb friction (1 N m; the Horizon Zero Dawn ragdoll
///   ships 2.5 and 5), so a limb hanging off a pile stops within a swing or two;
/// - sleeping.
const GAME: &str = r#"
solver = "simd"
substeps = 4
iterations = 4
joint_flavour = "exact"
contact_push_speed = 3.0
contact_extra_sweeps = 0
contact_warm_start = 1.0
contact_hertz = 90.0
contact_damping_ratio = 1.0
contact_stacking = 0.0
contact_stacking_max_ratio = inf
contact_detection = "frame"
joint_damping = 0.2
joint_friction = 1.0
sleep = true
"#;

/// Low error for the paper's 20 solves a frame. Over the drop's landings (layouts 1-128 x both
/// spines, 150 frames) the deepest overlap found afresh passes 1 cm on 5 of 256 and none
/// explodes, at 1.5x the paper's step time (docs/landings.md, Landings that hold):
/// - 20 substeps of one iteration (small steps buy more accuracy per solve than iterations);
/// - contacts found afresh every substep, so points follow limbs that slide over each other,
///   and six sweeps of the contacts alone after each substep's iteration;
/// - stacking: the lower body of a contact counts up to e times heavier (from 10 cm of height),
///   so the sweeps carry a pile's weight to the floor;
/// - exact joints: the cheap one-row hinge spins a squeezed forearm about its axis until it
///   explodes;
/// - overlap pushed out at no more than 5 m/s: at once, one substep's push-out of boxes started
///   inside each other is 1200 times their depth per second, and stacking and the sweeps throw
///   them at 90-200 m/s (`tests/it/methods.rs`); over the landings the cap leaves 5 of 256 over
///   1 cm where none left 7.
const TIGHT: &str = r#"
solver = "simd"
substeps = 20
iterations = 1
joint_flavour = "exact"
contact_push_speed = 5.0
contact_extra_sweeps = 6
contact_warm_start = 0.0
contact_hertz = 0.0
contact_damping_ratio = 1.0
contact_stacking = 10.0
contact_stacking_max_ratio = 2.718281828
contact_detection = "substep"
joint_damping = 0.0
joint_friction = 0.0
sleep = false
"#;

#[cfg(test)]
mod tests {
    use super::*;

    /// Every method decides the same fields, so one applied over another leaves nothing of it.
    #[test]
    fn every_method_sets_the_same_fields() {
        let keys = |m: Method| {
            let table: toml::Table = toml::from_str(m.settings_toml()).unwrap();
            table.keys().cloned().collect::<Vec<_>>()
        };
        for method in Method::ALL {
            let _ = method.overrides();
            assert_eq!(keys(method), keys(Method::Paper), "{method}");
        }
    }
}
