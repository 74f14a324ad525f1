//! The product speaks of itself in the present tense: no development history in the code,
//! the tests, the docs, the scenes or CI, and a README that stays a front page.

use std::path::{Path, PathBuf};

/// Every text file under `dir` (recursively), but the rig data the scenes read.
fn text_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if !path.ends_with("rigs") {
                text_files(&path, out);
            }
        } else if ["rs", "md", "toml", "sh"]
            .iter()
            .any(|e| path.extension().is_some_and(|x| x == *e))
        {
            out.push(path);
        }
    }
}

/// Words that tell the code's history: a numbered stop or issue, or what was dropped on the way.
#[test]
fn no_tracked_text_tells_the_development_history() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![
        root.join("README.md"),
        root.join("Cargo.toml"),
        root.join(".ci/run"),
    ];
    for dir in ["src", "tests", "benches", "docs", "scenes"] {
        text_files(&root.join(dir), &mut files);
    }
    // spelt in pieces, so this file does not match itself
    let numbered = [["st", "op "].concat(), ["iss", "ue "].concat()];
    let phrases = [
        ["this ", "stop"].concat(),
        ["uncom", "mitted"].concat(),
        ["not ", "kept"].concat(),
    ];
    let mut found = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            let numbered_hit = numbered.iter().any(|word| {
                lower.match_indices(word.as_str()).any(|(i, w)| {
                    let starts_word = i == 0 || !lower.as_bytes()[i - 1].is_ascii_alphabetic();
                    starts_word && lower[i + w.len()..].starts_with(|c: char| c.is_ascii_digit())
                })
            });
            if numbered_hit || phrases.iter().any(|p| lower.contains(p.as_str())) {
                found.push(format!("{}:{}: {line}", file.display(), n + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "history in tracked text:\n{}",
        found.join("\n")
    );
}

/// The README is a front page: at most 150 lines.
#[test]
fn the_readme_is_a_front_page() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 150, "README.md has {lines} lines");
}
