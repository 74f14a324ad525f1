//! What a declared setting is made of: its bounds, how its values read and print, and the
//! record [`Declaration`] that `rodlab settings`, the scene checks, the command line and the
//! sweep's labels read. The settings themselves are declared once, in
//! `method_settings!` (`solver::settings`).

/// The values a setting may take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bounds {
    /// Any value of its type (a choice, a switch).
    Any,
    /// A whole number from `min` to `max`.
    Count {
        /// The least value.
        min: u32,
        /// The greatest value.
        max: u32,
    },
    /// A number above `min` (or at it, when `min_included`) and at most `max`; an infinite
    /// `max` lets `inf` through (no limit), [`f32::MAX`] asks for a finite number.
    Number {
        /// The lower end.
        min: f32,
        /// Whether `min` itself is allowed.
        min_included: bool,
        /// The upper end, included.
        max: f32,
    },
}

impl Bounds {
    /// A finite number of `min` or more.
    pub const fn at_least(min: f32) -> Bounds {
        Bounds::Number {
            min,
            min_included: true,
            max: f32::MAX,
        }
    }

    /// A positive number, or `inf` for none.
    pub const fn positive_or_inf() -> Bounds {
        Bounds::Number {
            min: 0.0,
            min_included: false,
            max: f32::INFINITY,
        }
    }

    /// A number from `min` to `max`, both included.
    pub const fn from_to(min: f32, max: f32) -> Bounds {
        Bounds::Number {
            min,
            min_included: true,
            max,
        }
    }

    /// What a value must be, in words, with `unit` (empty: none), e.g. "a number of 0 or more
    /// (N m)".
    pub fn describe(&self, unit: &str) -> String {
        let unit = |text: String| match unit.is_empty() {
            true => text,
            false => format!("{text} ({unit})"),
        };
        match *self {
            Bounds::Any => "one of the choices".into(),
            Bounds::Count { min, max } => format!("a whole number from {min} to {max}"),
            Bounds::Number {
                min,
                min_included,
                max,
            } => {
                let low = match (min_included, min == 0.0) {
                    (true, _) => format!("{min} or more"),
                    (false, true) => "positive".into(),
                    (false, false) => format!("over {min}"),
                };
                match (max == f32::INFINITY, max == f32::MAX) {
                    (true, _) => unit(format!("{low}, or inf")),
                    (_, true) => unit(low),
                    _ if min_included => unit(format!("from {min} to {max}")),
                    _ => unit(format!("over {min} and at most {max}")),
                }
            }
        }
    }
}

/// A type a setting can have: read from the command line, checked against its bounds, printed
/// in labels and tables.
pub trait SettingValue: Clone + PartialEq + std::fmt::Display {
    /// Reads a command-line value (`inf` for an unlimited number, a choice by its scene name).
    fn parse_text(text: &str) -> Result<Self, String>;
    /// Whether the value lies within `bounds`.
    fn within(&self, bounds: &Bounds) -> bool;
    /// What values within `bounds` are, in words (`unit` for numbers).
    fn values(bounds: &Bounds, unit: &str) -> String {
        bounds.describe(unit)
    }

    /// The value if within `bounds`, or what it must be (`unit` for the message).
    fn checked(self, bounds: &Bounds, unit: &str) -> Result<Self, String> {
        match self.within(bounds) {
            true => Ok(self),
            false => Err(format!("must be {}, got {self}", bounds.describe(unit))),
        }
    }
}

impl SettingValue for f32 {
    fn parse_text(text: &str) -> Result<Self, String> {
        text.trim()
            .parse::<f32>()
            .map_err(|e| format!("{e}: {text:?}"))
    }
    fn within(&self, bounds: &Bounds) -> bool {
        match *bounds {
            Bounds::Number {
                min,
                min_included,
                max,
            } => {
                let low = if min_included {
                    *self >= min
                } else {
                    *self > min
                };
                low && *self <= max
            }
            Bounds::Count { min, max } => (min as f32..=max as f32).contains(self),
            Bounds::Any => !self.is_nan(),
        }
    }
}

impl SettingValue for u32 {
    fn parse_text(text: &str) -> Result<Self, String> {
        text.trim()
            .parse::<u32>()
            .map_err(|_| format!("not a whole number of 0 or more: {text:?}"))
    }
    fn within(&self, bounds: &Bounds) -> bool {
        match *bounds {
            Bounds::Count { min, max } => (min..=max).contains(self),
            Bounds::Number { .. } => (*self as f32).within(bounds),
            Bounds::Any => true,
        }
    }
}

impl SettingValue for bool {
    fn parse_text(text: &str) -> Result<Self, String> {
        text.trim()
            .parse::<bool>()
            .map_err(|_| format!("must be true or false, got {text:?}"))
    }
    fn within(&self, _: &Bounds) -> bool {
        true
    }
    fn values(_: &Bounds, _: &str) -> String {
        "true, false".into()
    }
}

/// A setting that is one of a few named choices, spelt as in scene files (its serde names,
/// listed after the type).
macro_rules! choice_setting {
    ($($ty:ty: $choices:literal),*) => {$(
        impl $crate::solver::declared::SettingValue for $ty {
            fn parse_text(text: &str) -> Result<Self, String> {
                $crate::solver::declared::parse_choice(text)
            }
            fn within(&self, _: &$crate::solver::declared::Bounds) -> bool {
                true
            }
            fn values(_: &$crate::solver::declared::Bounds, _: &str) -> String {
                $choices.into()
            }
        }
    )*};
}
pub(crate) use choice_setting;

/// Reads a choice the way scene files spell it (the enum's serde names).
pub fn parse_choice<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, String> {
    use serde::de::IntoDeserializer;
    T::deserialize(text.trim().into_deserializer())
        .map_err(|e: serde::de::value::Error| e.to_string().replace('`', "\""))
}

/// One declared setting, as `rodlab settings` and the docs list it.
#[derive(Clone, Copy, Debug)]
pub struct Declaration {
    /// The scene file's key (`contact_hertz`); the flag is the same with dashes.
    pub name: &'static str,
    /// What it does, from its doc comment.
    pub doc: &'static str,
    /// Its unit ("" for none).
    pub unit: &'static str,
    /// The values it may take.
    pub bounds: Bounds,
    /// Those values in words ("scalar, simd", "0 or more (N m)").
    pub values: fn() -> String,
    /// How a chart's line names a method whose value differs from the paper's: `{}` stands
    /// for the value ("x{}" for 4 substeps: " x4"); empty: never named.
    pub label: &'static str,
}

impl Declaration {
    /// The command line's flag: `--` and the key with dashes.
    pub fn flag(&self) -> String {
        format!("--{}", self.name.replace('_', "-"))
    }

    /// The label part of a line whose value prints as `value` (empty: unnamed).
    pub fn label_of(&self, value: &str) -> String {
        match self.label.is_empty() {
            true => String::new(),
            false => format!(" {}", self.label.replace("{}", value)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_say_what_a_value_must_be() {
        let positive = Bounds::positive_or_inf();
        assert!(f32::INFINITY.within(&positive) && 0.1.within(&positive));
        assert!(!0.0.within(&positive) && !f32::NAN.within(&positive));
        assert_eq!(
            0.0f32.checked(&positive, "m/s").unwrap_err(),
            "must be positive, or inf (m/s), got 0"
        );
        let finite = Bounds::at_least(0.0);
        assert!(!f32::INFINITY.within(&finite) && 0.0.within(&finite));
        assert_eq!(
            (-1.0f32).checked(&finite, "N m").unwrap_err(),
            "must be 0 or more (N m), got -1"
        );
        let fraction = Bounds::from_to(0.0, 1.0);
        assert!(!1.5.within(&fraction) && 1.0.within(&fraction));
        let count = Bounds::Count { min: 1, max: 10 };
        assert!(!0u32.within(&count) && 10u32.within(&count) && !11u32.within(&count));
        assert_eq!(
            11u32.checked(&count, "").unwrap_err(),
            "must be a whole number from 1 to 10, got 11"
        );
    }
}
