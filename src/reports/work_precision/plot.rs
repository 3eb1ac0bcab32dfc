//! The work-precision report's plot: error against wall time on log-log axes, as SVG.

use std::fmt::Write as _;

use super::point::Point;
use crate::solver::Formulation;

/// SVG log-log plot of error against time at tolerance 1e-8, one polyline per problem and
/// formulation (points along a line are the meshes).
pub fn svg(points: &[Point]) -> String {
    let pts: Vec<&Point> = points
        .iter()
        .filter(|p| p.tolerance == 1e-8 && p.error > 0.0)
        .collect();
    let (w, h, m) = (900.0, 600.0, 70.0);
    let lx = |t: f64| t.max(1e-7).log10();
    let ly = |e: f64| e.max(1e-16).log10();
    let (x0, x1) = (
        pts.iter()
            .map(|p| lx(p.seconds))
            .fold(f64::MAX, f64::min)
            .floor(),
        pts.iter()
            .map(|p| lx(p.seconds))
            .fold(f64::MIN, f64::max)
            .ceil(),
    );
    let (y0, y1) = (
        pts.iter()
            .map(|p| ly(p.error))
            .fold(f64::MAX, f64::min)
            .floor(),
        pts.iter()
            .map(|p| ly(p.error))
            .fold(f64::MIN, f64::max)
            .ceil(),
    );
    let sx = |t: f64| m + (lx(t) - x0) / (x1 - x0).max(1.0) * (w - 2.0 * m);
    let sy = |e: f64| h - m - (ly(e) - y0) / (y1 - y0).max(1.0) * (h - 2.0 * m);
    let mut s = format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n");
    for d in (x0 as i32)..=(x1 as i32) {
        let x = m + (d as f64 - x0) / (x1 - x0).max(1.0) * (w - 2.0 * m);
        let _ = writeln!(s, "<line x1=\"{x}\" y1=\"{m}\" x2=\"{x}\" y2=\"{}\" stroke=\"#ddd\"/><text x=\"{x}\" y=\"{}\" text-anchor=\"middle\">1e{d} s</text>", h - m, h - m + 18.0);
    }
    for d in (y0 as i32)..=(y1 as i32) {
        let y = h - m - (d as f64 - y0) / (y1 - y0).max(1.0) * (h - 2.0 * m);
        let _ = writeln!(s, "<line x1=\"{m}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#ddd\"/><text x=\"{}\" y=\"{}\" text-anchor=\"end\">1e{d}</text>", w - m, m - 6.0, y + 4.0);
    }
    let _ = writeln!(s, "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">wall time of the run (median)</text><text x=\"16\" y=\"{}\" transform=\"rotate(-90 16 {})\" text-anchor=\"middle\">error against the reference</text>", w / 2.0, h - 20.0, h / 2.0, h / 2.0);
    let colours = [
        "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf", "#7f7f7f",
    ];
    // One colour per problem, solid for Bernoulli-Euler and dashed for Timoshenko; a dot per mesh.
    let mut problems: Vec<&str> = Vec::new();
    for p in &pts {
        if !problems.contains(&p.problem.as_str()) {
            problems.push(&p.problem);
        }
    }
    let styles = [
        (Formulation::BernoulliEuler, ""),
        (Formulation::Timoshenko, " stroke-dasharray=\"6 3\""),
    ]
    .map(|(f, dash)| (f, f.name(), dash));
    for (k, prob) in problems.iter().enumerate() {
        let c = colours[k % colours.len()];
        for (f, _, dash) in styles {
            let line: Vec<(f64, f64)> = (pts.iter())
                .filter(|p| p.problem == *prob && p.formulation == f)
                .map(|p| (sx(p.seconds), sy(p.error)))
                .collect();
            let joined: Vec<String> = line.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
            let _ = writeln!(
                s,
                "<polyline points=\"{}\" fill=\"none\" stroke=\"{c}\" stroke-width=\"2\"{dash}/>",
                joined.join(" ")
            );
            for (x, y) in line {
                let _ = writeln!(
                    s,
                    "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"2.5\" fill=\"{c}\"/>"
                );
            }
        }
        let y = m + 16.0 * (k as f64 + 1.0);
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{y}\" fill=\"{c}\">{prob}</text>",
            w - m - 190.0
        );
    }
    for (i, (_, name, dash)) in styles.iter().enumerate() {
        let y = m + 16.0 * (problems.len() as f64 + 1.5 + i as f64);
        let x = w - m - 190.0;
        let _ = writeln!(
            s,
            "<line x1=\"{x}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#444\" stroke-width=\"2\"{dash}/><text x=\"{}\" y=\"{y}\" fill=\"#444\">{name}</text>",
            y - 4.0,
            x + 30.0,
            y - 4.0,
            x + 36.0
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" fill=\"#444\">dots: meshes of 4 to 1024 elements, tolerance 1e-8</text>",
        m + 10.0,
        h - m - 10.0
    );
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(problem: &str, formulation: Formulation, error: f64, seconds: f64) -> Point {
        Point {
            problem: problem.into(),
            formulation,
            elements: 4,
            tolerance: 1e-8,
            increments: 10,
            iterations: 40,
            error,
            seconds,
        }
    }

    /// The plot: one line per problem and formulation, a dot per point, both formulations of
    /// a problem in its colour (Timoshenko dashed), and a dot on the grid line of its decade:
    /// error 1e-3 at 1e-2 s sits where the 1e-3 and 1e-2 s grid lines cross (to 0.1 px).
    #[test]
    fn svg_places_points_on_log_axes() {
        let pts = [
            at("A", Formulation::BernoulliEuler, 1e-2, 1e-3),
            at("A", Formulation::BernoulliEuler, 1e-3, 1e-2),
            at("A", Formulation::Timoshenko, 1e-4, 1e-1),
            at("B", Formulation::BernoulliEuler, 1e-5, 1e-3),
        ];
        let s = svg(&pts);
        assert_eq!(
            s.matches("<polyline").count(),
            4,
            "2 problems x 2 formulations"
        );
        assert_eq!(s.matches("<circle").count(), 4);
        assert_eq!(
            s.matches("stroke-dasharray").count(),
            3,
            "2 lines and a legend"
        );
        // Decades 1e-3..1e-1 s over 900 - 2 * 70 px; 1e-5..1e-2 over 600 - 2 * 70 px.
        let x = 70.0 + (-2.0 + 3.0) / 2.0 * 760.0;
        let y = 600.0 - 70.0 - (-3.0 + 5.0) / 3.0 * 460.0;
        assert!(
            s.contains(&format!("<circle cx=\"{x:.1}\" cy=\"{y:.1}\"")),
            "{s}"
        );
        let dots_of_a = s.matches("fill=\"#1f77b4\"/>").count();
        assert_eq!(dots_of_a, 3);
    }
}
