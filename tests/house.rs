//! The house of modules (ARCHITECTURE.md, "The house"): a grep over `src/` that fails when a
//! module imports a name through `lib.rs`'s re-exports, or when a module outside the driver
//! imports a module its floor may not see.
//!
//! The check reads the source as text: comment lines are skipped, and an item marked
//! `#[cfg(test)]` (a unit-test module, a test helper) is held to the first rule only, since unit
//! tests may drive the whole pipeline.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// Plain data and the tools on it: each imports only others of its floor.
const GROUND: &[&str] = &[
    "binary",
    "csr",
    "curve3d",
    "decisions",
    "draw",
    "error",
    "geometry",
    "gray",
    "mask",
    "median",
    "node_graph",
    "params",
    "point_index",
    "point_set",
    "samples",
    "stroke_graph",
];

/// The stages, side by side over the ground floor.
const STAGES: &[&str] = &[
    "raster",
    "point_list",
    "cloud3d",
    "sample",
    "graph",
    "refine",
    "fit",
    "skeleton",
    "subpixel",
    "fingerprint",
    "warnings",
];

/// What is derived from a `StrokeGraph` alone.
const FEATURES: &[&str] = &["strokes", "minutiae", "curves"];

/// The writers, at the end of the chain: they read a trace (`pipeline`'s `Trace` and `Stages`),
/// the features' results and, for the pictures, the fingerprint front end's fields and the SVG
/// colours.
const WRITERS: &[(&str, &[&str])] = &[
    ("export", &["strokes", "minutiae", "curves", "pipeline"]),
    (
        "debug",
        &[
            "strokes",
            "minutiae",
            "curves",
            "pipeline",
            "fingerprint",
            "export",
        ],
    ),
];

/// Stages that build on a feature: the print's minutiae filter (`fingerprint/minutiae.rs`)
/// refines what `minutiae` detects on the traced graph with the print's own fields.
const STAGE_EXTRAS: &[(&str, &[&str])] = &[("fingerprint", &["minutiae"])];

/// The driver: chains the stages, so it may import any module.
const DRIVER: &[&str] = &["pipeline"];

/// Imports that break the rules and are known, each with the reason it is still there. The check
/// fails when one of them is no longer needed, so the list cannot outlive its reason.
const PENDING: &[(&str, &str, &str)] = &[];

/// What `lib.rs` declares: its re-exported names (with the module each comes from), its own
/// functions and its modules.
struct Crate {
    reexports: BTreeMap<String, String>,
    functions: BTreeSet<String>,
    modules: BTreeSet<String>,
}

fn identifier(text: &str) -> &str {
    let end = text
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(text.len());
    &text[..end]
}

/// The code of a line: nothing after `//` (a line comment, a doc comment), trimmed.
fn code(line: &str) -> &str {
    let mut in_string = false;
    let bytes = line.as_bytes();
    for i in 0..bytes.len() {
        match bytes[i] {
            b'"' if i == 0 || bytes[i - 1] != b'\\' => in_string = !in_string,
            b'/' if !in_string && bytes.get(i + 1) == Some(&b'/') => return line[..i].trim(),
            _ => {}
        }
    }
    line.trim()
}

/// The items of a brace group `{a, b::{C, D}, E}` at its top level, from just past `{`; returns
/// them and the length read up to the matching `}`.
fn group_items(text: &str) -> (Vec<String>, usize) {
    let mut depth = 1;
    let mut items = vec![String::new()];
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    let items = items
                        .iter()
                        .map(|s| s.trim().to_string())
                        .filter(|s| !s.is_empty())
                        .collect();
                    return (items, i);
                }
            }
            ',' if depth == 1 => {
                items.push(String::new());
                continue;
            }
            _ => {}
        }
        if let Some(last) = items.last_mut() {
            last.push(c);
        }
    }
    (Vec::new(), text.len())
}

fn parse_lib(lib: &str) -> Crate {
    let text: String = lib.lines().map(code).collect::<Vec<_>>().join("\n");
    let mut reexports = BTreeMap::new();
    let mut rest = text.as_str();
    while let Some(at) = rest.find("pub use ") {
        let statement = &rest[at + "pub use ".len()..];
        let end = statement.find(';').unwrap_or(statement.len());
        let statement = &statement[..end];
        if let Some(open) = statement.find('{') {
            let module = statement[..open].trim_end_matches("::").to_string();
            for item in group_items(&statement[open + 1..]).0 {
                let name = item.rsplit(" as ").next().unwrap_or(&item).trim();
                reexports.insert(name.to_string(), module.clone());
            }
        } else if let Some((module, name)) = statement.rsplit_once("::") {
            let name = name.rsplit(" as ").next().unwrap_or(name).trim();
            reexports.insert(name.to_string(), module.to_string());
        }
        rest = &rest[at + 1..];
    }
    let mut functions = BTreeSet::new();
    let mut modules = BTreeSet::new();
    // Items of lib.rs's own unit tests (a helper module for them) are none of the crate's.
    let lines: Vec<&str> = text.lines().collect();
    let in_test = test_lines(&lines);
    for (line, _) in lines.iter().zip(&in_test).filter(|(_, &test)| !test) {
        // Top-level items only: they start at column 0.
        for prefix in ["pub fn ", "pub(crate) fn ", "fn "] {
            if let Some(rest) = line.strip_prefix(prefix) {
                functions.insert(identifier(rest).to_string());
            }
        }
        for prefix in ["mod ", "pub mod ", "pub(crate) mod "] {
            if let Some(rest) = line.strip_prefix(prefix) {
                modules.insert(identifier(rest).to_string());
            }
        }
    }
    Crate {
        reexports,
        functions,
        modules,
    }
}

/// For each line of `source`, whether it belongs to an item marked `#[cfg(test)]`.
fn test_lines(source: &[&str]) -> Vec<bool> {
    let mut marked = vec![false; source.len()];
    let mut i = 0;
    while i < source.len() {
        if code(source[i]) != "#[cfg(test)]" {
            i += 1;
            continue;
        }
        let mut depth = 0i64;
        let mut opened = false;
        while i < source.len() {
            marked[i] = true;
            let line = code(source[i]);
            // Braces inside character literals do not count.
            let line = line.replace("'{'", "").replace("'}'", "");
            depth += line.matches('{').count() as i64 - line.matches('}').count() as i64;
            opened |= line.contains('{');
            i += 1;
            let attribute = line.starts_with("#[");
            if !attribute && ((opened && depth <= 0) || (!opened && line.ends_with(';'))) {
                break;
            }
        }
    }
    marked
}

/// The floor a top-level module stands on, and the modules it may import besides its own
/// submodules; `None` for the driver (anything).
fn allowed(module: &str) -> Option<BTreeSet<&'static str>> {
    if DRIVER.contains(&module) {
        return None;
    }
    let mut set: BTreeSet<&str> = GROUND.iter().copied().collect();
    if let Some((_, extra)) = WRITERS
        .iter()
        .chain(STAGE_EXTRAS)
        .find(|(name, _)| *name == module)
    {
        set.extend(extra.iter().copied());
    }
    Some(set)
}

/// The first path segments named after `crate::` on a line: `crate::a::B` names `a`, and
/// `crate::{a, B}` names `a` and `B`.
fn crate_names(line: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut rest = line;
    while let Some(at) = rest.find("crate::") {
        let after = &rest[at + "crate::".len()..];
        if let Some(group) = after.strip_prefix('{') {
            let (items, _) = group_items(group);
            names.extend(items.iter().map(|item| identifier(item).to_string()));
        } else {
            names.push(identifier(after).to_string());
        }
        rest = after;
    }
    names.retain(|n| !n.is_empty() && n != "self");
    names
}

/// Every breach of the rules in `files` (path relative to the repository, text), given `lib.rs`.
fn violations(lib: &str, files: &[(String, String)]) -> Vec<String> {
    let krate = parse_lib(lib);
    let mut found = Vec::new();
    let mut pending_used = BTreeSet::new();
    for (path, text) in files {
        if path == "src/lib.rs" {
            continue;
        }
        let module = path
            .trim_start_matches("src/")
            .split('/')
            .next()
            .unwrap_or("")
            .trim_end_matches(".rs")
            .to_string();
        let may_import = allowed(&module);
        let lines: Vec<&str> = text.lines().collect();
        let in_test = test_lines(&lines);
        // A `use crate::{` group may run over several lines: read each statement whole.
        let mut statement = String::new();
        let mut start = 0;
        for (i, line) in lines.iter().enumerate() {
            let line = code(line);
            if statement.is_empty() {
                start = i;
            }
            statement.push_str(line);
            statement.push(' ');
            let open = statement.matches('{').count() > statement.matches('}').count();
            if open && statement.trim_start().starts_with("use crate::{") {
                continue;
            }
            for name in crate_names(&statement) {
                let pending = PENDING.iter().find(|(p, n, _)| p == path && *n == name);
                let breach = if let Some(from) = krate.reexports.get(&name) {
                    Some(format!(
                        "`crate::{name}` is lib.rs's re-export: import it from `crate::{}`",
                        from.trim_start_matches("crate::")
                    ))
                } else if krate.functions.contains(&name) && !in_test[start] {
                    Some(format!(
                        "`crate::{name}` calls the public entry from inside the crate"
                    ))
                } else if krate.modules.contains(&name)
                    && name != module
                    && !in_test[start]
                    && may_import
                        .as_ref()
                        .is_some_and(|set| !set.contains(name.as_str()))
                {
                    Some(format!("`{module}` may not import the module `{name}`"))
                } else {
                    None
                };
                if let Some(breach) = breach {
                    if pending.is_some() {
                        pending_used.insert((path.clone(), name.clone()));
                    } else {
                        found.push(format!("{path}:{}: {breach}", start + 1));
                    }
                }
            }
            statement.clear();
        }
    }
    for (path, name, reason) in PENDING {
        let known = files.iter().any(|(p, _)| p == path);
        if known && !pending_used.contains(&(path.to_string(), name.to_string())) {
            found.push(format!(
                "{path} no longer needs `{name}` ({reason}): remove it from PENDING in tests/house.rs"
            ));
        }
    }
    found
}

fn sources(dir: &Path, root: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .expect("list src")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            sources(&path, root, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let name = path.strip_prefix(root).expect("under root");
            let name = name.to_string_lossy().replace('\\', "/");
            out.push((name, fs::read_to_string(&path).expect("read source")));
        }
    }
}

#[test]
fn no_module_imports_through_the_driver_or_past_its_floor() {
    let root = crate::support::repository_root();
    let lib = fs::read_to_string(root.join("src/lib.rs")).expect("read lib.rs");
    let mut files = Vec::new();
    sources(&root.join("src"), root, &mut files);
    assert!(files.len() > 50, "read {} files of src/", files.len());
    let found = violations(&lib, &files);
    assert!(
        found.is_empty(),
        "the house (ARCHITECTURE.md):\n{}",
        found.join("\n")
    );
}

#[test]
fn every_module_of_lib_rs_has_a_floor() {
    let root = crate::support::repository_root();
    let lib = fs::read_to_string(root.join("src/lib.rs")).expect("read lib.rs");
    let krate = parse_lib(&lib);
    let placed: BTreeSet<&str> = GROUND
        .iter()
        .chain(STAGES)
        .chain(FEATURES)
        .chain(DRIVER)
        .copied()
        .chain(WRITERS.iter().map(|(name, _)| *name))
        .collect();
    let unplaced: Vec<&String> = krate
        .modules
        .iter()
        .filter(|m| !placed.contains(m.as_str()))
        .collect();
    assert!(unplaced.is_empty(), "modules without a floor: {unplaced:?}");
    assert!(krate.reexports.contains_key("StrokeGraph"));
    assert!(krate.functions.contains("trace_binary"));
}

/// The check finds what it is meant to find: a re-export by name, in a group over several
/// lines, a stage importing another stage, a stage calling the public entry; and it lets unit
/// tests drive the pipeline.
#[test]
fn the_check_finds_each_kind_of_breach() {
    let lib = "mod binary;\nmod stroke_graph;\npub mod sample;\npub mod graph;\nmod pipeline;\n\
               pub use binary::{Binary, MaskView};\npub use stroke_graph::StrokeGraph;\n\
               pub fn trace_binary() {}\n";
    let file = |path: &str, text: &str| (path.to_string(), text.to_string());
    let files = [
        file("src/sample.rs", "use crate::{Binary, stroke_graph::StrokeGraph};\n"),
        file(
            "src/graph.rs",
            "use crate::{\n    binary::Binary,\n    MaskView,\n};\nuse crate::sample::run;\n\
             fn f() { crate::trace_binary(); }\n\
             // use crate::StrokeGraph; in a comment\n\
             #[cfg(test)]\nmod tests {\n    fn t() { crate::trace_binary(); crate::sample::run(); }\n}\n",
        ),
        file("src/pipeline.rs", "use crate::{graph, sample};\nuse crate::binary::Binary;\n"),
    ];
    let found = violations(lib, &files);
    let expected = [
        "src/sample.rs:1: `crate::Binary` is lib.rs's re-export: import it from `crate::binary`",
        "src/graph.rs:1: `crate::MaskView` is lib.rs's re-export: import it from `crate::binary`",
        "src/graph.rs:5: `graph` may not import the module `sample`",
        "src/graph.rs:6: `crate::trace_binary` calls the public entry from inside the crate",
    ];
    assert_eq!(found, expected);
}
