//! The sweep's CSV table: writing the rows and reading them back (the columns are listed in
//! the [`crate::sweep`] module docs; one per method setting).

use super::SweepRow;
use crate::solver::METHOD_SETTINGS;
use crate::world::Settings;

/// The columns before the method settings', and after them.
const LEADING: [&str; 3] = ["method", "spine", "joint"];
const TRAILING: [&str; 7] = [
    "step_us",
    "mean_dislocation_cm",
    "max_dislocation_cm",
    "mean_angular_rad",
    "max_angular_rad",
    "max_overlap_cm",
    "failed",
];

/// The header: the leading columns, one per method setting, the measures.
fn header() -> String {
    let settings = METHOD_SETTINGS.iter().map(|d| d.name);
    (LEADING.into_iter().chain(settings).chain(TRAILING))
        .collect::<Vec<_>>()
        .join(",")
}

/// The rows as CSV text, header first (see the [`crate::sweep`] module docs for the columns).
pub fn to_csv(rows: &[SweepRow]) -> String {
    crate::csv_table::to_text(
        &header(),
        rows.iter().map(|r| {
            let mut fields = vec![r.method.clone(), r.spine.clone(), r.joint.clone()];
            fields.extend(r.settings.method_texts().into_iter().map(|(_, text)| text));
            fields.extend([
                format!("{:.3}", r.step_us),
                format!("{:.6}", r.mean_dislocation_cm),
                format!("{:.6}", r.max_dislocation_cm),
                format!("{:.6}", r.mean_angular_rad),
                format!("{:.6}", r.max_angular_rad),
                format!("{:.4}", r.max_overlap_cm),
                r.failed.clone().unwrap_or_default(),
            ]);
            fields
        }),
    )
}

/// Reads back what [`to_csv`] wrote; errors name the line and the column.
pub fn parse_csv(text: &str) -> anyhow::Result<Vec<SweepRow>> {
    use anyhow::Context as _;
    let header = header();
    let columns: Vec<&str> = header.split(',').collect();
    let measures = LEADING.len() + METHOD_SETTINGS.len();
    let mut rows = Vec::new();
    for (line, fields) in crate::csv_table::read(text, &header)? {
        let number = |column: usize| -> anyhow::Result<f64> {
            fields[column]
                .parse::<f64>()
                .with_context(|| format!("line {line}: column {}: not a number", columns[column]))
        };
        let mut settings = Settings::default();
        for (i, declared) in METHOD_SETTINGS.iter().enumerate() {
            let text = &fields[LEADING.len() + i];
            (settings.set_method_text(declared.name, text))
                .map_err(|e| anyhow::anyhow!("line {line}: column {}: {e}", declared.name))?;
        }
        rows.push(SweepRow {
            method: fields[0].to_string(),
            spine: fields[1].to_string(),
            joint: fields[2].to_string(),
            settings,
            step_us: number(measures)?,
            mean_dislocation_cm: number(measures + 1)?,
            max_dislocation_cm: number(measures + 2)?,
            mean_angular_rad: number(measures + 3)?,
            max_angular_rad: number(measures + 4)?,
            max_overlap_cm: number(measures + 5)?,
            failed: Some(fields[measures + 6].to_string()).filter(|s| !s.is_empty()),
        });
    }
    Ok(rows)
}
