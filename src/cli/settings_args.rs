//! The method settings as command-line flags, derived from their one declaration
//! (`method_settings!` (`solver::settings`)): an optional flag each for `run`,
//! `all` and `layouts` (and a `--set key=value` each), and a comma-separated list each for
//! `sweep`. A value is checked against the setting's declared bounds, the same bounds as a
//! scene file's.

use clap::Args;

use crate::sim::Overrides;
use crate::solver::SettingValue;
use crate::sweep::SettingLists;

/// The method settings `run --help` shows as flags of their own; the others stay flags but
/// are listed through `--set` (`rodlab settings`), so the help fits on a screen.
const SHOWN: [&str; 2] = ["iterations", "substeps"];

/// Defines [`MethodFlags`] and [`MethodListFlags`].
macro_rules! method_flags {
    ({} $( $(#[doc = $doc:literal])* $name:ident : $ty:ty = $default:expr,
        unit $unit:literal, bounds $bounds:expr, label $label:literal; )*) => {
        /// The method settings, each overriding the scene's (and its `--method`'s); `rodlab
        /// settings` lists their units, bounds and defaults.
        #[derive(Debug, Clone, Default, Args)]
        #[command(next_help_heading = "Method settings (`rodlab settings` lists units and bounds)")]
        pub struct MethodFlags {
            $(
                $(#[doc = $doc])*
                #[arg(long, hide = !SHOWN.contains(&stringify!($name)),
                      value_parser = |s: &str| <$ty as SettingValue>::parse_text(s)?.checked(&$bounds, $unit))]
                pub $name: Option<$ty>,
            )*
        }

        /// Sets the method setting `key` of `overrides` from its text, checked against the
        /// setting's bounds (`--set key=value`); `Ok(false)` when `key` is no method setting.
        pub fn set_method_setting(
            overrides: &mut Overrides,
            key: &str,
            text: &str,
        ) -> Result<bool, String> {
            match key {
                $( stringify!($name) => {
                    let value = <$ty as SettingValue>::parse_text(text)?.checked(&$bounds, $unit)?;
                    overrides.$name = Some(value);
                    Ok(true)
                } )*
                _ => Ok(false),
            }
        }

        impl MethodFlags {
            /// Writes the flags given into `overrides`.
            pub fn write_into(&self, overrides: &mut Overrides) {
                $( if self.$name.is_some() {
                    overrides.$name = self.$name.clone();
                } )*
            }
        }

        /// The method settings as the sweep's dimensions: comma-separated values each, an
        /// unset one keeping the scene's (or each named method's) value.
        #[derive(Debug, Clone, Default, Args)]
        #[command(next_help_heading = "Method settings, comma-separated values, one dimension each (`rodlab settings` lists them)")]
        pub struct MethodListFlags {
            $(
                $(#[doc = $doc])*
                #[arg(long, value_delimiter = ',', value_parser = |s: &str| <$ty as SettingValue>::parse_text(s)?.checked(&$bounds, $unit))]
                pub $name: Vec<$ty>,
            )*
        }

        impl From<MethodListFlags> for SettingLists {
            fn from(flags: MethodListFlags) -> Self {
                SettingLists { $( $name: flags.$name, )* }
            }
        }
    };
}
crate::solver::method_settings!(method_flags! {});
