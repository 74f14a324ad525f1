//! `rodlab benchmarks`: the criterion benchmarks' results as data, one CSV per machine (as Box2D
//! keeps `benchmark/<machine>/*.csv`): every benchmark criterion last measured under
//! `target/criterion`, its median time with criterion's 95% interval, and the time per element
//! where the benchmark names a throughput.

use std::path::{Path, PathBuf};

use anyhow::Context;

/// One benchmark's last measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// criterion's full id: group/function/value.
    pub id: String,
    /// Median time per iteration (ns) and criterion's 95% interval of it.
    pub median_ns: f64,
    pub median_low_ns: f64,
    pub median_high_ns: f64,
    /// Elements per iteration, where the benchmark names a throughput.
    pub elements: Option<u64>,
}

/// Every benchmark measured under `criterion` (criterion's output folder), sorted by id.
pub fn read_criterion(criterion: &Path) -> anyhow::Result<Vec<Measured>> {
    let mut found = Vec::new();
    collect(criterion, &mut found)?;
    found.sort_by(|a: &Measured, b| a.id.cmp(&b.id));
    Ok(found)
}

fn collect(dir: &Path, found: &mut Vec<Measured>) -> anyhow::Result<()> {
    let entries = std::fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))?;
    for entry in entries {
        let path = entry?.path();
        if !path.is_dir() {
            continue;
        }
        let (benchmark, estimates) = (path.join("benchmark.json"), path.join("estimates.json"));
        if path.file_name().is_some_and(|n| n == "new") && estimates.is_file() {
            found.push(measured(&benchmark, &estimates)?);
        } else {
            collect(&path, found)?;
        }
    }
    Ok(())
}

/// One benchmark from criterion's `benchmark.json` and `estimates.json`.
fn measured(benchmark: &Path, estimates: &Path) -> anyhow::Result<Measured> {
    let read =
        |p: &Path| std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()));
    let (about, times) = (read(benchmark)?, read(estimates)?);
    let bad = |what: &str, p: &Path| anyhow::anyhow!("{}: no {what}", p.display());
    let id = string_after(&about, "\"full_id\":").ok_or_else(|| bad("full_id", benchmark))?;
    let median = &times[times
        .find("\"median\":")
        .ok_or_else(|| bad("median", estimates))?..];
    let number = |key: &str| number_after(median, key).ok_or_else(|| bad(key, estimates));
    Ok(Measured {
        id,
        median_ns: number("\"point_estimate\":")?,
        median_low_ns: number("\"lower_bound\":")?,
        median_high_ns: number("\"upper_bound\":")?,
        elements: number_after(&about, "\"Elements\":").map(|n| n as u64),
    })
}

/// The JSON string right after `key` (criterion's ids hold no escaped quotes).
fn string_after(text: &str, key: &str) -> Option<String> {
    let rest = text[text.find(key)? + key.len()..]
        .trim_start()
        .strip_prefix('"')?;
    Some(rest[..rest.find('"')?].to_string())
}

/// The JSON number right after the first `key`.
fn number_after(text: &str, key: &str) -> Option<f64> {
    let rest = text[text.find(key)? + key.len()..].trim_start();
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].trim().parse().ok()
}

/// The machine's folder name: [`crate::machine::name`] in lower case, words joined by dashes.
pub fn machine_folder(machine: &str) -> String {
    let words: Vec<String> = (machine.split(|c: char| !c.is_ascii_alphanumeric()))
        .filter(|w| !w.is_empty())
        .map(str::to_ascii_lowercase)
        .collect();
    words.join("-")
}

/// The CSV of `rows`, measured on `machine`.
pub fn csv(machine: &str, rows: &[Measured]) -> String {
    let records = rows.iter().map(|r| {
        let (elements, per) = match r.elements {
            Some(n) if n > 0 => (n.to_string(), format!("{:.3}", r.median_ns / n as f64)),
            _ => (String::new(), String::new()),
        };
        vec![
            r.id.clone(),
            format!("{:.1}", r.median_ns),
            format!("{:.1}", r.median_low_ns),
            format!("{:.1}", r.median_high_ns),
            elements,
            per,
            machine.to_string(),
        ]
    });
    crate::csv_table::to_text(
        "benchmark,median_ns,median_low_ns,median_high_ns,elements,median_ns_per_element,machine",
        records,
    )
}

/// Reads `criterion` and writes `<out>/<machine>/criterion.csv`; returns its path.
pub fn write(criterion: &Path, out: &Path) -> anyhow::Result<PathBuf> {
    let rows = read_criterion(criterion)?;
    anyhow::ensure!(
        !rows.is_empty(),
        "{}: no criterion results; run `cargo bench` first",
        criterion.display()
    );
    let machine = crate::machine::name();
    let folder = out.join(machine_folder(&machine));
    std::fs::create_dir_all(&folder).with_context(|| format!("creating {}", folder.display()))?;
    let path = folder.join("criterion.csv");
    std::fs::write(&path, csv(&machine, &rows))
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// criterion's two files for one benchmark, read back into a row of the CSV.
    #[test]
    fn a_benchmark_is_read_from_criterions_files() {
        let dir = std::env::temp_dir().join(format!("rodlab_bench_{}", std::process::id()));
        let new = dir.join("solve").join("rod_scalar").join("new");
        std::fs::create_dir_all(&new).unwrap();
        std::fs::write(
            new.join("benchmark.json"),
            r#"{"group_id":"solve","function_id":"rod/scalar","value_str":null,"throughput":{"Elements":64},"full_id":"solve/rod/scalar","directory_name":"solve/rod_scalar","title":"solve/rod/scalar"}"#,
        )
        .unwrap();
        std::fs::write(
            new.join("estimates.json"),
            r#"{"mean":{"confidence_interval":{"confidence_level":0.95,"lower_bound":1.0,"upper_bound":2.0},"point_estimate":1.5,"standard_error":0.1},"median":{"confidence_interval":{"confidence_level":0.95,"lower_bound":6390.5,"upper_bound":6420.25},"point_estimate":6400.0,"standard_error":3.0}}"#,
        )
        .unwrap();
        let rows = read_criterion(&dir).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let expected = Measured {
            id: "solve/rod/scalar".into(),
            median_ns: 6400.0,
            median_low_ns: 6390.5,
            median_high_ns: 6420.25,
            elements: Some(64),
        };
        assert_eq!(rows, [expected]);
        let text = csv("CPU X, 2 cores", &rows);
        assert!(
            text.ends_with("solve/rod/scalar,6400.0,6390.5,6420.2,64,100.000,\"CPU X, 2 cores\"\n"),
            "{text}"
        );
        assert_eq!(
            machine_folder("AMD EPYC (family 25, AVX-512), 2 cores"),
            "amd-epyc-family-25-avx-512-2-cores"
        );
    }
}
