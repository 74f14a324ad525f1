//! CSV output of the lab's tables (sweep, stress, tuning, feature costs) through the `csv`
//! crate, so a field holding a comma, a quote or a newline (a failure message) is quoted and
//! reads back whole instead of being rewritten. Numbers are formatted by the callers (fixed
//! decimals per column), so the files stay as readable as before.

/// `header` (comma-separated column names) and one record per row, as CSV text.
pub fn to_text(header: &str, rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    // writing to memory fails only on a record of the wrong width, a bug of the caller
    writer
        .write_record(header.split(','))
        .expect("CSV header into memory");
    for row in rows {
        writer.write_record(&row).expect("CSV row into memory");
    }
    let bytes = writer.into_inner().expect("CSV flush into memory");
    String::from_utf8(bytes).expect("CSV of UTF-8 fields is UTF-8")
}

/// The records of `text` after checking its header is `header`; errors name the line.
pub fn read(text: &str, header: &str) -> anyhow::Result<Vec<(u64, csv::StringRecord)>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes());
    let mut records = reader.records();
    let expected: Vec<&str> = header.split(',').collect();
    match records.next() {
        Some(Ok(first)) if first.iter().eq(expected.iter().copied()) => {}
        _ => anyhow::bail!("line 1: expected the header {header}"),
    }
    let mut rows = Vec::new();
    for record in records {
        let record = record.map_err(|e| match e.position() {
            Some(p) => anyhow::anyhow!("line {}: {e}", p.line()),
            None => anyhow::anyhow!("{e}"),
        })?;
        let line = record.position().map_or(0, |p| p.line());
        if record.len() != expected.len() {
            anyhow::bail!(
                "line {line}: {} columns, expected {}",
                record.len(),
                expected.len()
            );
        }
        rows.push((line, record));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    /// A field with a comma, a quote and a newline reads back whole, in its column.
    #[test]
    fn awkward_fields_round_trip() {
        let message = "frame 3: body \"drop1/head\", joint \"neck\",\nexploded";
        let text = super::to_text("a,failed", [vec!["1".into(), message.to_string()]]);
        let rows = super::read(&text, "a,failed").unwrap();
        assert_eq!(rows.len(), 1);
        assert_eq!((&rows[0].1[0], &rows[0].1[1]), ("1", message));
        let error = super::read("a,b\n1,2,3\n", "a,b").unwrap_err().to_string();
        assert!(error.contains("line 2"), "{error}");
    }
}
