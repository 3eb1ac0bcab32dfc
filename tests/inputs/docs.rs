//! The documentation against the program: every RON block in README.md and docs/ is a valid
//! scene, every `solve` and `scenes` command the README shows runs, the README's sample output
//! is what `solve` prints (but for the times), and docs/cli.md is what `--help` prints.

use std::path::{Path, PathBuf};
use std::process::Command;

use tsm_contact::scene::parse;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The fenced blocks of `text` whose info string is `lang`.
fn blocks(text: &str, lang: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        match &mut current {
            None if line.trim_start() == format!("```{lang}") => current = Some(String::new()),
            Some(_) if line.trim_start().starts_with("```") => out.extend(current.take()),
            Some(b) => {
                b.push_str(line);
                b.push('\n');
            }
            None => {}
        }
    }
    out
}

/// README.md and every Markdown file in docs/.
fn pages() -> Vec<(PathBuf, String)> {
    let mut paths = vec![root().join("README.md")];
    for e in std::fs::read_dir(root().join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            paths.push(p);
        }
    }
    paths
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p, text)
        })
        .collect()
}

fn run(dir: &Path, args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

#[test]
fn every_ron_block_in_the_docs_is_a_valid_scene() {
    let mut count = 0;
    for (path, text) in pages() {
        for (k, b) in blocks(&text, "ron").into_iter().enumerate() {
            if let Err(e) = parse(&b, &format!("{} block {k}", path.display())) {
                panic!("{e}");
            }
            count += 1;
        }
    }
    assert!(count >= 2, "{count} blocks");
}

/// The README's `solve` and `scenes` commands, in a folder holding its tutorial scene
/// (`first.ron`, the README's RON block): each exits with status 0. `view`, `bench` and `stress`
/// are left to the GUI and report tests.
#[test]
fn the_readme_commands_run() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let dir = std::env::temp_dir().join(format!("tsm-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = blocks(&readme, "ron")
        .into_iter()
        .next()
        .expect("tutorial scene");
    std::fs::write(dir.join("first.ron"), scene).unwrap();
    let mut ran = 0;
    for b in blocks(&readme, "sh") {
        for line in b.lines() {
            let line = line.split('#').next().unwrap_or("").trim();
            let Some(args) = line.strip_prefix("cargo run --release -- ") else {
                continue;
            };
            let args: Vec<&str> = args.split_whitespace().collect();
            if !matches!(args.first(), Some(&"solve" | &"scenes")) {
                continue;
            }
            let (code, _) = run(&dir, &args);
            assert_eq!(code, 0, "`{line}`");
            ran += 1;
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(ran >= 4, "{ran} commands");
}

/// The sample output in the README is `solve example_3_2 --steps 12`'s, line for line, but for
/// the times (the last column of an increment line, and the total).
#[test]
fn the_readme_sample_output_is_the_programs() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let sample = blocks(&readme, "text")
        .into_iter()
        .next()
        .expect("sample output");
    let (code, out) = run(&root(), &["solve", "example_3_2", "--steps", "12"]);
    assert_eq!(code, 0);
    let without_time = |l: &str| -> String {
        let l = l.trim_end();
        if l.starts_with("# ") && l.contains(" ms") {
            return l.split(',').take(2).collect::<Vec<_>>().join(",");
        }
        match l.split_whitespace().next().map(|w| w.parse::<usize>()) {
            Some(Ok(_)) => l.rsplit_once(' ').map_or(l, |(a, _)| a).trim_end().into(),
            _ => l.into(),
        }
    };
    let lines: Vec<String> = out.lines().map(without_time).collect();
    for s in sample.lines().filter(|l| *l != "...") {
        let s = without_time(s);
        assert!(lines.contains(&s), "README line not printed: {s}\n{out}");
    }
}

/// docs/cli.md holds each subcommand's `--help` as printed.
#[test]
fn the_cli_reference_is_the_help() {
    let page = std::fs::read_to_string(root().join("docs/cli.md")).unwrap();
    let printed = blocks(&page, "text");
    let commands = [
        "solve", "scenes", "check", "view", "figure", "bench", "stress", "robust", "scale",
    ];
    assert_eq!(printed.len(), commands.len());
    for (c, shown) in commands.iter().zip(&printed) {
        let (code, help) = run(&root(), &[c, "--help"]);
        assert_eq!(code, 0);
        let trimmed: String = help
            .lines()
            .map(|l| format!("{}\n", l.trim_end()))
            .collect();
        assert_eq!(
            &trimmed, shown,
            "`tsm-contact {c} --help` differs from docs/cli.md"
        );
        assert!(
            help.contains("Example: tsm-contact"),
            "{c}: no example line"
        );
    }
}

/// The README's validation errors are the program's, to the two figures shown: each `bench`
/// row is worked out again (release build: about a second in all).
#[cfg(feature = "reports")]
#[test]
fn the_readme_validation_errors_are_the_programs() {
    use tsm_contact::reports::work_precision as wp;
    use tsm_contact::solver::Formulation::{BernoulliEuler, Timoshenko};
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let shown = |problem: &str| -> f64 {
        let row = (readme.lines())
            .find(|l| l.starts_with(&format!("| {problem} |")))
            .unwrap_or_else(|| panic!("no README row for {problem}"));
        let error = row.split('|').nth(3).expect("error column").trim();
        error
            .split_whitespace()
            .next()
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{problem}: error `{error}`"))
    };
    let rows = [
        (
            "Mattiasson's cantilever, k = 10, 1024 elements",
            wp::mattiasson(2, 1024, BernoulliEuler, 1e-8, 1),
        ),
        (
            "End moment 2 pi EI / L, 1024 elements",
            wp::end_moment(1024, BernoulliEuler, 1e-8, 1),
        ),
        (
            "Pin on a cantilever, 1024 Timoshenko elements",
            wp::pin_contact(1024, Timoshenko, 1e-8, 1),
        ),
        (
            "Pin on a cantilever, 1024 Bernoulli-Euler elements",
            wp::pin_contact(1024, BernoulliEuler, 1e-8, 1),
        ),
    ];
    for (problem, point) in rows {
        let error = point.expect("converges").error;
        let readme_error = shown(problem);
        assert!(
            (error - readme_error).abs() <= 0.05 * readme_error,
            "{problem}: the program gives {error:.2e}, the README {readme_error:.1e}"
        );
    }
}

/// docs/validation.md's tables are docs/work-precision.csv's errors at tolerance 1e-8, to the
/// two figures shown.
#[test]
fn the_validation_tables_are_the_work_precision_points() {
    let page = std::fs::read_to_string(root().join("docs/validation.md")).unwrap();
    let points = std::fs::read_to_string(root().join("docs/work-precision.csv")).unwrap();
    let mut rows = points.lines();
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (p, f, n, t, e) = (
        col("problem"),
        col("formulation"),
        col("elements"),
        col("tolerance"),
        col("error"),
    );
    let mut checked = 0;
    let mut problem = String::new();
    let mut meshes: Vec<String> = Vec::new();
    for line in page.lines() {
        if let Some(name) = line.strip_prefix("### ") {
            problem = name.to_string();
        } else if let Some(rest) = line.strip_prefix("| elements |") {
            meshes = rest.split('|').map(|s| s.trim().to_string()).collect();
        } else if line.starts_with("| Bernoulli-Euler |") || line.starts_with("| Timoshenko |") {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let formulation = cells[1].replace('-', "");
            for (mesh, shown) in meshes.iter().zip(&cells[2..]) {
                let Ok(shown) = shown.parse::<f64>() else {
                    continue;
                };
                let point = points.lines().skip(1).find(|l| {
                    let c: Vec<&str> = l.split(',').collect();
                    c[p] == problem
                        && c[f] == formulation
                        && c[n] == mesh
                        && c[t].parse::<f64>() == Ok(1e-8)
                });
                let error: f64 = point
                    .expect("a point")
                    .split(',')
                    .nth(e)
                    .unwrap()
                    .parse()
                    .unwrap();
                assert!(
                    (error - shown).abs() <= 0.051 * shown,
                    "{problem}, {formulation}, {mesh}: {shown} shown, {error} in the CSV"
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 80, "{checked} values checked");
}

/// The user guide lists every keyboard shortcut the app's help window lists.
#[cfg(feature = "gui")]
#[test]
fn the_user_guide_lists_every_shortcut() {
    let guide = std::fs::read_to_string(root().join("docs/user-guide.md")).unwrap();
    for (key, _) in tsm_contact::app::panels::shortcuts::SHORTCUTS {
        let first = key.split(" / ").next().unwrap().split(',').next().unwrap();
        assert!(
            guide.contains(&format!("| {first}")) || guide.contains(&format!(", {first} |")),
            "docs/user-guide.md has no row for {key}"
        );
    }
}
