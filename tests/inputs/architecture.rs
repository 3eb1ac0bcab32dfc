//! The arrows between the parts of `src/`: reads the sources, builds the graph of which file
//! imports which (through `use` trees and inline `crate::`/`super::` paths, with re-exports
//! followed to the file that defines the item) and checks that
//! - no two files import each other, directly or round a circle;
//! - inside every folder, its entries (files and sub-folders) import each other without a
//!   circle;
//! - the solver imports nothing from the scene, the worker, the app, the reports or the CLI;
//!   its linear algebra nothing from the elements or contact;
//! - no file in `src/` has 500 lines or more, and no folder holds more than 10 files.
//!
//! The graph is that of the code that ships: `#[cfg(test)]` modules are left out (unit tests
//! may use any fixture).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One source file: its module path in its crate, and the crate (`lib` or `bin`).
struct File {
    krate: &'static str,
    module: Vec<String>,
    text: String,
}

/// Source text with comments, string and char literals blanked and `#[cfg(test)]` items cut.
fn strip(src: &str) -> String {
    let b: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied().unwrap_or(' ');
        if c == '/' && next == '/' {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == '*' {
            i += 2;
            while i + 1 < b.len() && !(b[i] == '*' && b[i + 1] == '/') {
                i += 1;
            }
            i += 2;
        } else if c == 'r' && (next == '"' || next == '#') && !ident_char(prev(&b, i)) {
            let mut j = i + 1;
            let mut hashes = 0;
            while j < b.len() && b[j] == '#' {
                hashes += 1;
                j += 1;
            }
            if j < b.len() && b[j] == '"' {
                j += 1;
                loop {
                    if j >= b.len() {
                        break;
                    }
                    if b[j] == '"' && (0..hashes).all(|h| b.get(j + 1 + h) == Some(&'#')) {
                        j += 1 + hashes;
                        break;
                    }
                    j += 1;
                }
                out.push_str("\"\"");
                i = j;
            } else {
                out.push(c);
                i += 1;
            }
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                i += if b[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' && next == '\\' {
            i += 2;
            while i < b.len() && b[i] != '\'' {
                i += 1;
            }
            i += 1;
            out.push_str("' '");
        } else if c == '\'' && b.get(i + 2) == Some(&'\'') {
            i += 3;
            out.push_str("' '");
        } else {
            out.push(c);
            i += 1;
        }
    }
    cut_test_items(&out)
}

fn prev(b: &[char], i: usize) -> char {
    if i == 0 {
        ' '
    } else {
        b[i - 1]
    }
}

fn ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// `s` without the items marked `#[cfg(test)]` (a block up to its closing brace, or a
/// declaration up to its semicolon).
fn cut_test_items(s: &str) -> String {
    let mut out = String::new();
    let mut rest = s;
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let after = &rest[at + "#[cfg(test)]".len()..];
        let semi = after.find(';').unwrap_or(after.len());
        let brace = after.find('{').unwrap_or(after.len());
        if semi < brace {
            rest = &after[(semi + 1).min(after.len())..];
        } else {
            let mut depth = 0;
            let mut end = after.len();
            for (k, ch) in after.char_indices().skip(brace) {
                match ch {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            end = k + 1;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            rest = &after[end..];
        }
    }
    out.push_str(rest);
    out
}

/// The `mod name;` declarations of a stripped source (its child modules kept in files).
fn declared_modules(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (k, _) in text.match_indices("mod ") {
        if k > 0 && ident_char(text[..k].chars().last().unwrap_or(' ')) {
            continue;
        }
        let tail = &text[k + 4..];
        let name: String = tail.chars().take_while(|c| ident_char(*c)).collect();
        if !name.is_empty() && tail[name.len()..].trim_start().starts_with(';') {
            out.push(name);
        }
    }
    out
}

/// Every file reachable from `root` (lib.rs or main.rs) through `mod` declarations.
fn collect(src: &Path, krate: &'static str, root: &str, files: &mut BTreeMap<PathBuf, File>) {
    let mut todo = vec![(src.join(root), Vec::<String>::new())];
    while let Some((path, module)) = todo.pop() {
        let raw = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let text = strip(&raw);
        let dir = match path.file_name().and_then(|f| f.to_str()) {
            Some("mod.rs" | "lib.rs" | "main.rs") => path.parent().unwrap().to_path_buf(),
            _ => path.with_extension(""),
        };
        for child in declared_modules(&text) {
            let flat = dir.join(format!("{child}.rs"));
            let nested = dir.join(&child).join("mod.rs");
            let file = if flat.exists() { flat } else { nested };
            let mut m = module.clone();
            m.push(child);
            todo.push((file, m));
        }
        files.insert(
            path,
            File {
                krate,
                module,
                text,
            },
        );
    }
}

/// The paths a stripped source names, each as a list of segments as written (with `crate`,
/// `super`, `self` or a crate name first), and the inline module it is written in.
fn paths(text: &str) -> Vec<(Vec<String>, Vec<String>)> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut scope: Vec<(String, i32)> = Vec::new();
    let mut depth = 0;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '{' {
            depth += 1;
            i += 1;
            continue;
        }
        if c == '}' {
            depth -= 1;
            if scope.last().is_some_and(|(_, d)| *d == depth) {
                scope.pop();
            }
            i += 1;
            continue;
        }
        if !ident_char(c) || ident_char(prev(&chars, i)) {
            i += 1;
            continue;
        }
        let word: String = chars[i..].iter().take_while(|c| ident_char(**c)).collect();
        let inner: Vec<String> = scope.iter().map(|(n, _)| n.clone()).collect();
        if word == "mod" {
            let rest: String = chars[i + 3..].iter().collect();
            let name: String = rest
                .trim_start()
                .chars()
                .take_while(|c| ident_char(*c))
                .collect();
            let after = rest.trim_start()[name.len()..].trim_start();
            if after.starts_with('{') {
                scope.push((name, depth));
            }
            i += 3;
        } else if word == "use" {
            let end = (i..chars.len())
                .find(|&k| chars[k] == ';')
                .unwrap_or(chars.len());
            let tree: String = chars[i + 3..end].iter().collect();
            for p in expand(&tree) {
                out.push((p, inner.clone()));
            }
            i = end;
        } else {
            // An inline path: identifiers joined by `::`.
            let mut segs = vec![word.clone()];
            let mut k = i + word.len();
            while chars.get(k) == Some(&':') && chars.get(k + 1) == Some(&':') {
                let seg: String = chars[k + 2..]
                    .iter()
                    .take_while(|c| ident_char(**c))
                    .collect();
                if seg.is_empty() {
                    break;
                }
                k += 2 + seg.len();
                segs.push(seg);
            }
            if segs.len() > 1 {
                out.push((segs, inner.clone()));
            }
            i = k;
        }
    }
    out
}

/// The paths of a `use` tree (`a::{b, c::{d, e}}` gives a::b, a::c::d, a::c::e).
fn expand(tree: &str) -> Vec<Vec<String>> {
    // Aliases dropped (`x as y`: the path is x's), then the whitespace.
    let mut words = Vec::new();
    let mut alias = false;
    for w in tree.split_whitespace() {
        if w == "as" {
            alias = true;
        } else if std::mem::take(&mut alias) {
            words.push(w.trim_start_matches(|c: char| ident_char(c)).to_string());
        } else {
            words.push(w.to_string());
        }
    }
    let t: String = words.concat();
    let t = t.trim_start_matches("::");
    fn go(prefix: &[String], t: &str, out: &mut Vec<Vec<String>>) {
        let mut segs: Vec<String> = prefix.to_vec();
        let mut rest = t;
        loop {
            if let Some(inner) = rest.strip_prefix('{') {
                let inner = &inner[..inner.len().saturating_sub(1)];
                for part in split_top(inner) {
                    go(&segs, part, out);
                }
                return;
            }
            let end = rest.find("::").unwrap_or(rest.len());
            let seg = &rest[..end];
            if !seg.is_empty() && seg != "*" {
                segs.push(seg.chars().take_while(|c| ident_char(*c)).collect());
            }
            if end == rest.len() {
                out.push(segs);
                return;
            }
            rest = &rest[end + 2..];
        }
    }
    let mut out = Vec::new();
    go(&[], t, &mut out);
    out
}

/// The parts of a comma list at brace depth 0.
fn split_top(s: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (k, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&s[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    parts.push(&s[start..]);
    parts.into_iter().filter(|p| !p.is_empty()).collect()
}

/// The module graph of `src/`.
struct Graph {
    files: BTreeMap<PathBuf, File>,
    /// (crate, module path) to file.
    modules: BTreeMap<(&'static str, Vec<String>), PathBuf>,
    /// Re-exports: (file, name) to the absolute path it stands for.
    reexports: BTreeMap<(PathBuf, String), Vec<String>>,
}

impl Graph {
    fn new(src: &Path) -> Graph {
        let mut files = BTreeMap::new();
        collect(src, "lib", "lib.rs", &mut files);
        collect(src, "bin", "main.rs", &mut files);
        let modules = files
            .iter()
            .map(|(p, f)| ((f.krate, f.module.clone()), p.clone()))
            .collect();
        let mut g = Graph {
            files,
            modules,
            reexports: BTreeMap::new(),
        };
        let mut reexports = BTreeMap::new();
        for (path, f) in &g.files {
            for (k, _) in f.text.match_indices("pub use ") {
                let end = f.text[k..].find(';').map_or(f.text.len(), |e| k + e);
                for p in expand(&f.text[k + 8..end]) {
                    if let Some(abs) = g.absolute(f, &[], &p) {
                        if let Some(name) = abs.1.last() {
                            reexports.insert((path.clone(), name.clone()), abs.1.clone());
                        }
                    }
                }
            }
        }
        g.reexports = reexports;
        g
    }

    /// The absolute (crate, segments) of `p` written in `f` inside inline modules `inner`;
    /// None for a path into another crate.
    fn absolute(
        &self,
        f: &File,
        inner: &[String],
        p: &[String],
    ) -> Option<(&'static str, Vec<String>)> {
        let mut here: Vec<String> = f.module.iter().chain(inner).cloned().collect();
        let first = p.first()?.as_str();
        let (krate, rest): (&'static str, &[String]) = match first {
            "crate" => (f.krate, &p[1..]),
            "tsm_contact" => ("lib", &p[1..]),
            "self" => {
                return Some((f.krate, here.into_iter().chain(p[1..].to_vec()).collect()));
            }
            "super" => {
                let mut k = 0;
                while p.get(k).map(String::as_str) == Some("super") {
                    here.pop();
                    k += 1;
                }
                return Some((f.krate, here.into_iter().chain(p[k..].to_vec()).collect()));
            }
            _ => {
                // A path relative to the current module, if it starts with a child module.
                let mut child = f.module.clone();
                child.push(first.to_string());
                if inner.is_empty() && self.modules.contains_key(&(f.krate, child)) {
                    return Some((f.krate, f.module.iter().chain(p).cloned().collect()));
                }
                return None;
            }
        };
        Some((krate, rest.to_vec()))
    }

    /// The file that defines what `abs` names (re-exports followed).
    fn target(&self, abs: &(&'static str, Vec<String>)) -> Option<PathBuf> {
        let mut abs = abs.clone();
        for _ in 0..16 {
            let mut n = abs.1.len();
            let file = loop {
                if let Some(file) = self.modules.get(&(abs.0, abs.1[..n].to_vec())) {
                    break file.clone();
                }
                if n == 0 {
                    return None;
                }
                n -= 1;
            };
            match abs.1.get(n) {
                Some(name) => match self.reexports.get(&(file.clone(), name.clone())) {
                    Some(to) if *to != abs.1 => {
                        let mut next = to.clone();
                        next.extend_from_slice(&abs.1[n + 1..]);
                        abs = (abs.0, next);
                    }
                    _ => return Some(file),
                },
                None => return Some(file),
            }
        }
        None
    }

    /// Every (importer, imported) pair of files.
    fn edges(&self) -> BTreeSet<(PathBuf, PathBuf)> {
        let mut out = BTreeSet::new();
        for (path, f) in &self.files {
            for (p, inner) in paths(&f.text) {
                let Some(abs) = self.absolute(f, &inner, &p) else {
                    continue;
                };
                if let Some(to) = self.target(&abs) {
                    if to != *path {
                        out.insert((path.clone(), to));
                    }
                }
            }
        }
        out
    }
}

/// The circles of a directed graph (its strongly connected components of more than one node).
fn circles<N: Ord + Clone>(edges: &BTreeSet<(N, N)>) -> Vec<Vec<N>> {
    let nodes: BTreeSet<N> = edges
        .iter()
        .flat_map(|(a, b)| [a.clone(), b.clone()])
        .collect();
    let reach = |from: &N| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.clone()];
        while let Some(n) = todo.pop() {
            for (a, b) in edges {
                if *a == n && seen.insert(b.clone()) {
                    todo.push(b.clone());
                }
            }
        }
        seen
    };
    let reachable: BTreeMap<N, BTreeSet<N>> = nodes.iter().map(|n| (n.clone(), reach(n))).collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for n in &nodes {
        if done.contains(n) || !reachable[n].contains(n) {
            continue;
        }
        let comp: Vec<N> = nodes
            .iter()
            .filter(|m| reachable[n].contains(*m) && reachable[*m].contains(n))
            .cloned()
            .collect();
        done.extend(comp.iter().cloned());
        out.push(comp);
    }
    out
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rel(p: &Path) -> String {
    p.strip_prefix(src()).unwrap_or(p).display().to_string()
}

#[test]
fn no_file_imports_itself_round_a_circle() {
    let g = Graph::new(&src());
    let found = circles(&g.edges());
    let text: Vec<String> = found
        .iter()
        .map(|c| c.iter().map(|p| rel(p)).collect::<Vec<_>>().join(" <-> "))
        .collect();
    assert!(text.is_empty(), "import circles:\n{}", text.join("\n"));
}

/// The entry of folder `dir` that holds `file` (a file directly in it, or a sub-folder).
fn entry(dir: &Path, file: &Path) -> String {
    let rest = file.strip_prefix(dir).expect("inside");
    rest.components()
        .next()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .unwrap_or_default()
}

#[test]
fn no_folder_has_a_circle_between_its_entries() {
    let g = Graph::new(&src());
    let mut by_dir: BTreeMap<PathBuf, BTreeSet<(String, String)>> = BTreeMap::new();
    for (a, b) in g.edges() {
        // The deepest folder holding both.
        let mut dir = a.parent().unwrap().to_path_buf();
        while !b.starts_with(&dir) {
            dir = dir.parent().unwrap().to_path_buf();
        }
        let (ea, eb) = (entry(&dir, &a), entry(&dir, &b));
        if ea != eb {
            by_dir.entry(dir).or_default().insert((ea, eb));
        }
    }
    let mut text = Vec::new();
    for (dir, edges) in &by_dir {
        for c in circles(edges) {
            text.push(format!("{}: {}", rel(dir), c.join(" <-> ")));
        }
    }
    assert!(
        text.is_empty(),
        "circles between folder entries:\n{}",
        text.join("\n")
    );
}

/// The imports from files under `from` into files under any of `into`.
fn arrows(g: &Graph, from: &str, into: &[&str]) -> Vec<String> {
    let root = src();
    g.edges()
        .into_iter()
        .filter(|(a, b)| {
            a.starts_with(root.join(from)) && into.iter().any(|i| b.starts_with(root.join(i)))
        })
        .map(|(a, b)| format!("{} -> {}", rel(&a), rel(&b)))
        .collect()
}

#[test]
fn the_solver_imports_nothing_from_the_layers_above_it() {
    let g = Graph::new(&src());
    let wrong = arrows(
        &g,
        "solver",
        &[
            "scene",
            "worker",
            "worker.rs",
            "app",
            "reports",
            "cli",
            "history.rs",
            "main.rs",
        ],
    );
    assert!(
        wrong.is_empty(),
        "solver arrows running upwards:\n{}",
        wrong.join("\n")
    );
}

/// The audit is the tests' oracle: it reads histories with its own geometry and sums, and
/// shares no code with what it checks.
#[test]
fn the_audit_shares_no_code_with_the_solver_it_checks() {
    let g = Graph::new(&src());
    let wrong = arrows(
        &g,
        "audit",
        &[
            "solver/contact",
            "solver/acceptance",
            "solver/element",
            "solver/newton",
            "solver/assembly",
            "solver/control",
            "solver/linear",
            "solver/structure.rs",
        ],
    );
    assert!(
        wrong.is_empty(),
        "audit arrows into the solver's code:\n{}",
        wrong.join("\n")
    );
    assert!(src().join("audit").is_dir(), "audit/ holds the oracle");
}

#[test]
fn the_linear_algebra_knows_no_element_and_no_contact() {
    let g = Graph::new(&src());
    let wrong = arrows(
        &g,
        "solver/linear",
        &["solver/element", "solver/contact", "solver/assembly"],
    );
    assert!(
        wrong.is_empty(),
        "linear algebra arrows:\n{}",
        wrong.join("\n")
    );
    assert!(
        src().join("solver/linear").is_dir(),
        "solver/linear/ holds the linear algebra"
    );
}

#[test]
fn files_read_in_one_sitting_and_folders_stay_small() {
    let g = Graph::new(&src());
    let mut long = Vec::new();
    let mut per_dir: BTreeMap<PathBuf, usize> = BTreeMap::new();
    for path in g.files.keys() {
        let lines = std::fs::read_to_string(path).unwrap().lines().count();
        if lines >= 500 {
            long.push(format!("{}: {lines} lines", rel(path)));
        }
        *per_dir
            .entry(path.parent().unwrap().to_path_buf())
            .or_default() += 1;
    }
    assert!(
        long.is_empty(),
        "files of 500 lines or more:\n{}",
        long.join("\n")
    );
    let crowded: Vec<String> = (per_dir.iter())
        .filter(|(_, n)| **n > 10)
        .map(|(d, n)| format!("{}: {n} files", rel(d)))
        .collect();
    assert!(
        crowded.is_empty(),
        "folders of more than 10 files:\n{}",
        crowded.join("\n")
    );
}

/// An obstacle shape lives in three files: its format and checks (`scene/shape.rs`), every
/// geometric question the solver asks of it (`solver/model/shape.rs`) and the audit's own
/// geometry (`audit/obstacles.rs`). No other file takes a shape apart by its variants, and the
/// audit asks the solver's shape nothing but where it lies once moved (`translated`): the
/// oracle measures with code of its own.
#[test]
fn an_obstacle_shape_lives_in_three_files() {
    let g = Graph::new(&src());
    let variants = ["Line", "Polyline", "Circle", "Arc"];
    let mut matched = BTreeSet::new();
    for (path, file) in &g.files {
        let text = &file.text;
        for v in variants {
            for enum_name in ["Shape", "ShapeDef"] {
                let pat = format!("{enum_name}::{v}");
                // The solver's and the format's variants are structs (`Shape::Circle {`);
                // egui's shapes of the same names are tuples (`Shape::Circle(`).
                let found = text.match_indices(&pat).any(|(i, _)| {
                    let rest = text[i + pat.len()..].trim_start();
                    rest.starts_with('{') && !text[..i].ends_with("egui::")
                });
                if found {
                    matched.insert(rel(path));
                }
            }
        }
    }
    let expected: BTreeSet<String> = [
        "audit/obstacles.rs",
        "scene/shape.rs",
        "solver/model/shape.rs",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    assert_eq!(matched, expected, "files that take an obstacle shape apart");
    let shape = std::fs::read_to_string(src().join("solver/model/shape.rs")).unwrap();
    let methods: Vec<&str> = (shape.split("pub fn ").skip(1))
        .filter_map(|m| m.split_once("(&self"))
        .map(|(name, _)| name)
        .filter(|name| *name != "translated")
        .collect();
    assert!(methods.contains(&"gap") && methods.contains(&"depth_inside"));
    for (path, file) in g.files.iter().filter(|(p, _)| rel(p).starts_with("audit/")) {
        for m in &methods {
            // A shape is held as `shape` or `o.shape` wherever the audit has one.
            assert!(
                !file.text.contains(&format!("shape.{m}(")),
                "{} calls the solver's Shape::{m}",
                rel(path)
            );
        }
    }
}

/// The checks above find what they look for: a circle and an upward arrow written into
/// sources of a scratch tree.
#[test]
fn the_checks_find_a_planted_circle_and_an_upward_arrow() {
    let dir = std::env::temp_dir().join(format!("tsm-arch-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("solver")).unwrap();
    std::fs::write(dir.join("lib.rs"), "pub mod solver;\npub mod scene;\n").unwrap();
    std::fs::write(dir.join("main.rs"), "fn main() {}\n").unwrap();
    std::fs::write(
        dir.join("solver/mod.rs"),
        "pub mod a;\npub mod b;\npub use a::A;\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("solver/a.rs"),
        "use super::b::{B, C};\n/// \"use crate::scene::S;\"\npub struct A;\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("solver/b.rs"),
        "pub struct B;\npub struct C;\nfn f() { let _ = crate::scene::S; let _ = super::A; }\n#[cfg(test)]\nmod tests { use crate::scene::T; }\n",
    )
    .unwrap();
    std::fs::write(dir.join("scene.rs"), "pub struct S;\npub struct T;\n").unwrap();
    let g = Graph::new(&dir);
    let edges = g.edges();
    let e = |a: &str, b: &str| edges.contains(&(dir.join(a), dir.join(b)));
    assert!(e("solver/a.rs", "solver/b.rs"));
    assert!(
        e("solver/b.rs", "solver/a.rs"),
        "super::A follows the re-export to a.rs"
    );
    assert!(e("solver/b.rs", "scene.rs"));
    assert_eq!(circles(&edges).len(), 1);
    assert_eq!(edges.len(), 4, "{edges:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The import graph, one arrow per line, for a reader tracing a circle:
/// `cargo test --test architecture -- --ignored --nocapture` (`ARROWS_FROM=solver/contact`
/// keeps the arrows from files under that folder).
#[test]
#[ignore]
fn print_the_import_graph() {
    let g = Graph::new(&src());
    let from = std::env::var("ARROWS_FROM").unwrap_or_default();
    for (a, b) in g.edges() {
        if rel(&a).starts_with(&from) {
            println!("{} -> {}", rel(&a), rel(&b));
        }
    }
}
