//! Value parsers for the command line's options: each refuses a bad value with a message
//! saying what it must be.

/// Parses a choice the way scene files spell it (the enum's serde names).
pub(crate) fn parse_choice<T: serde::de::DeserializeOwned>(s: &str) -> Result<T, String> {
    use serde::de::IntoDeserializer;
    T::deserialize(s.into_deserializer())
        .map_err(|e: serde::de::value::Error| e.to_string().replace('`', "\""))
}

/// A fraction in [0, 1] (alpha_b, alpha_t, warm starting).
pub(super) fn unit_interval(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        Ok(v) => Err(format!("must lie in [0, 1], got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// A number of 0 or more.
pub(super) fn non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v >= 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("must be 0 or more, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// A positive, finite time step (s).
pub(super) fn positive_seconds(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("must be a positive number of seconds, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// A positive, finite stiffness (N m/rad).
pub(super) fn positive_stiffness(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("must be a positive stiffness in N m/rad, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// A positive speed (m/s), or inf for no limit.
pub(super) fn positive_speed(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 => Ok(v),
        Ok(v) => Err(format!("must be a positive speed in m/s (or inf), got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// A positive angular speed (rad/s), or inf for no limit.
pub(super) fn positive_angular_speed(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 => Ok(v),
        Ok(v) => Err(format!("must be a positive angular speed in rad/s (or inf), got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// A contact stacking rate (1/m) from 0 to the scene bound.
pub(super) fn stacking_rate(s: &str) -> Result<f32, String> {
    let max = crate::scene::MAX_CONTACT_STACKING;
    match s.parse::<f32>() {
        Ok(v) if (0.0..=max).contains(&v) => Ok(v),
        Ok(v) => Err(format!("must be a rate from 0 to {max} per metre, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}
