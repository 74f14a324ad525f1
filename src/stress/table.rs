//! The suite's tables: verdicts as markdown (cases by methods) and one CSV row per run.

use super::{tripped, Criteria, Method, Outcome};

/// Rows: cases; columns: methods; cells: the verdict and its key number (the criterion that
/// tripped, or the mean residual of a stable run); `-` where a case does not apply.
pub fn table_markdown(outcomes: &[Outcome]) -> String {
    let mut cases: Vec<&str> = Vec::new();
    for o in outcomes {
        if !cases.contains(&o.case) {
            cases.push(o.case);
        }
    }
    let mut out = String::from("| case |");
    for method in Method::ALL {
        out += &format!(" {method} |");
    }
    out += "\n|---|";
    out += &"---|".repeat(Method::ALL.len());
    out += "\n";
    for case in cases {
        out += &format!("| {case} |");
        for method in Method::ALL {
            let cell = match outcomes
                .iter()
                .find(|o| o.case == case && o.method == method)
            {
                None => "-".to_string(),
                Some(o) => match tripped(&o.measures, &Criteria::default()) {
                    Some((v, why)) => format!("{v} ({why})"),
                    None => format!("{} ({:.2} cm)", o.verdict, o.measures.mean_residual_cm),
                },
            };
            out += &format!(" {} |", cell.replace('|', "/"));
        }
        out += "\n";
    }
    out
}

/// Column names of [`table_csv`].
pub const CSV_HEADER: &str = "case,method,verdict,frames_run,frames,energy_growth,\
final_energy_growth,peak_speed_m_s,speed_reference_m_s,final_speed_m_s,settles,max_residual_cm,mean_residual_cm,mean_angular_rad,\
shake_m_s,failed";

/// One row per run, columns [`CSV_HEADER`] (the failure message quoted where it needs it).
pub fn table_csv(outcomes: &[Outcome]) -> String {
    crate::csv_table::to_text(
        CSV_HEADER,
        outcomes.iter().map(|o| {
            let m = &o.measures;
            vec![
                o.case.to_string(),
                o.method.to_string(),
                o.verdict.to_string(),
                m.frames_run.to_string(),
                m.frames.to_string(),
                format!("{:.4}", m.energy_growth),
                format!("{:.4}", m.final_energy_growth),
                format!("{:.3}", m.peak_speed),
                format!("{:.3}", m.speed_reference),
                format!("{:.4}", m.final_speed),
                m.settles.to_string(),
                format!("{:.4}", m.max_residual_cm),
                format!("{:.4}", m.mean_residual_cm),
                format!("{:.4}", m.mean_angular_rad),
                format!("{:.4}", m.shake),
                m.failed.clone().unwrap_or_default(),
            ]
        }),
    )
}
