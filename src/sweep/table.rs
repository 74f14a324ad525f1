//! The sweep's CSV table: writing the rows and reading them back (the columns are listed in
//! the [`crate::sweep`] module docs).

use super::SweepRow;
use crate::world::ContactDetection;

const HEADER: &str =
    "method,spine,joint,solver,substeps,warm_start,contact_hertz,contact_stacking,contact_detection,contact_extra_sweeps,dt,iterations,step_us,\
mean_dislocation_cm,max_dislocation_cm,mean_angular_rad,max_angular_rad,max_overlap_cm,failed";

/// The rows as CSV text, header first (see the [`crate::sweep`] module docs for the columns).
pub fn to_csv(rows: &[SweepRow]) -> String {
    crate::csv_table::to_text(
        HEADER,
        rows.iter().map(|r| {
            vec![
                r.method.clone(),
                r.spine.clone(),
                r.joint.clone(),
                r.solver.clone(),
                r.substeps.to_string(),
                r.warm_start.to_string(),
                r.contact_hertz.to_string(),
                r.contact_stacking.to_string(),
                r.contact_detection.to_string(),
                r.contact_extra_sweeps.to_string(),
                r.dt.to_string(),
                r.iterations.to_string(),
                format!("{:.3}", r.step_us),
                format!("{:.6}", r.mean_dislocation_cm),
                format!("{:.6}", r.max_dislocation_cm),
                format!("{:.6}", r.mean_angular_rad),
                format!("{:.6}", r.max_angular_rad),
                format!("{:.4}", r.max_overlap_cm),
                r.failed.clone().unwrap_or_default(),
            ]
        }),
    )
}

/// Reads back what [`to_csv`] wrote (columns as in the [`crate::sweep`] module's table: method,
/// spine, joint, solver, substeps, warm_start, contact_hertz, contact_stacking, contact_detection,
/// contact_extra_sweeps, dt, iterations, step_us, the four residuals, max_overlap_cm, failed); errors name the line and the column.
pub fn parse_csv(text: &str) -> anyhow::Result<Vec<SweepRow>> {
    use anyhow::Context as _;
    let mut rows = Vec::new();
    for (line, fields) in crate::csv_table::read(text, HEADER)? {
        let number = |column: usize| -> anyhow::Result<f64> {
            fields[column].parse::<f64>().with_context(|| {
                let name = HEADER.split(',').nth(column).unwrap_or("?");
                format!("line {line}: column {name}: not a number")
            })
        };
        rows.push(SweepRow {
            method: fields[0].to_string(),
            spine: fields[1].to_string(),
            joint: fields[2].to_string(),
            solver: fields[3].to_string(),
            substeps: number(4)? as u32,
            warm_start: number(5)? as f32,
            contact_hertz: number(6)? as f32,
            contact_stacking: number(7)? as f32,
            contact_detection: match &fields[8] {
                "frame" => ContactDetection::Frame,
                "substep" => ContactDetection::Substep,
                other => anyhow::bail!(
                    "line {line}: column contact_detection: expected frame or substep, got {other:?}"
                ),
            },
            contact_extra_sweeps: number(9)? as u32,
            dt: number(10)? as f32,
            iterations: number(11)? as u32,
            step_us: number(12)?,
            mean_dislocation_cm: number(13)?,
            max_dislocation_cm: number(14)?,
            mean_angular_rad: number(15)?,
            max_angular_rad: number(16)?,
            max_overlap_cm: number(17)?,
            failed: Some(fields[18].to_string()).filter(|s| !s.is_empty()),
        });
    }
    Ok(rows)
}
