//! Maps between byte spans in a TOML text and field paths like `ragdoll[1].spine`, so every
//! scene error names the file, the line and the field.

use std::ops::Range;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// One step of a field path.
#[derive(Clone, Debug, PartialEq)]
pub enum Seg {
    Key(String),
    Index(usize),
}

/// Renders a path as `a.b[2].c`.
pub fn render(path: &[Seg]) -> String {
    let mut out = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(k);
            }
            Seg::Index(i) => out.push_str(&format!("[{i}]")),
        }
    }
    out
}

/// 1-based line of byte offset `offset`.
pub fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

/// The spanned document tree, or None if the text is not valid TOML.
pub fn parse(text: &str) -> Option<Spanned<DeTable<'_>>> {
    DeTable::parse(text).ok()
}

/// The top-level keys of scene text that parses (values are not read, so a number too large
/// for any type is still a key here).
pub fn top_level_keys(text: &str) -> Vec<String> {
    parse(text).map_or_else(Vec::new, |doc| {
        (doc.get_ref().iter())
            .map(|(key, _)| key.get_ref().to_string())
            .collect()
    })
}

/// The deepest path whose key or value span contains `span`. Searches the whole tree, since
/// the span of an array-of-tables entry covers only its `[[header]]`, not its keys.
pub fn path_at(root: &DeTable<'_>, span: &Range<usize>) -> Vec<Seg> {
    find_in_table(root, span, &mut Vec::new()).unwrap_or_default()
}

fn find_in_table(
    table: &DeTable<'_>,
    span: &Range<usize>,
    path: &mut Vec<Seg>,
) -> Option<Vec<Seg>> {
    for (key, value) in table.iter() {
        path.push(Seg::Key(key.get_ref().to_string()));
        let found = find_in_value(value, span, path).or_else(|| {
            (contains(&key.span(), span) || contains(&value.span(), span)).then(|| path.clone())
        });
        path.pop();
        if found.is_some() {
            return found;
        }
    }
    None
}

fn find_in_value(
    value: &Spanned<DeValue<'_>>,
    span: &Range<usize>,
    path: &mut Vec<Seg>,
) -> Option<Vec<Seg>> {
    match value.get_ref() {
        DeValue::Table(table) => find_in_table(table, span, path),
        DeValue::Array(items) => items.iter().enumerate().find_map(|(i, item)| {
            path.push(Seg::Index(i));
            let found = find_in_value(item, span, path)
                .or_else(|| contains(&item.span(), span).then(|| path.clone()));
            path.pop();
            found
        }),
        _ => None,
    }
}

/// Span of the deepest existing prefix of `path` (a missing field points at its table).
pub fn span_of(root: &Spanned<DeTable<'_>>, path: &[Seg]) -> Range<usize> {
    let mut best = root.span();
    let mut current: Option<&Spanned<DeValue<'_>>> = None;
    let mut table: Option<&DeTable<'_>> = Some(root.get_ref());
    for seg in path {
        let next = match (seg, table, current) {
            (Seg::Key(k), Some(t), _) => {
                t.iter()
                    .find(|(key, _)| key.get_ref() == k)
                    .map(|(key, v)| {
                        best = key.span();
                        v
                    })
            }
            (Seg::Index(i), _, Some(v)) => match v.get_ref() {
                DeValue::Array(items) => items.get(*i).inspect(|item| best = item.span()),
                _ => None,
            },
            _ => None,
        };
        let Some(next) = next else { break };
        current = Some(next);
        table = match next.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    best
}

fn contains(outer: &Range<usize>, inner: &Range<usize>) -> bool {
    outer.start <= inner.start && inner.end <= outer.end && outer.start < outer.end
}
