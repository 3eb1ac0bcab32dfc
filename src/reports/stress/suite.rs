//! The stability suite as a whole: every case for both formulations (`suite`), and its Markdown
//! table (`markdown`).

use super::cases::*;
use super::run::StressRow;
use crate::solver::Formulation;

/// Every case of the suite, both formulations. `long` adds the expensive variants.
pub fn suite(long: bool) -> Vec<StressRow> {
    let mut rows = Vec::new();
    for f in [Formulation::Timoshenko, Formulation::BernoulliEuler] {
        for xi in [0.9, 0.97, 0.99, 0.999, 0.9999] {
            rows.push(pin_near_end(xi, f).row);
        }
        rows.push(slide_across(50, f).row);
        rows.push(pressed_flat(f, if long { 40 } else { 10 }).row);
        rows.push(stacked(16, f).row);
        rows.push(stacked(17, f).row);
        for s in [1e1, 1e2, 1e3, 1e4] {
            rows.push(slender(s, f).row);
        }
        for s in [1.0, 2.0, 5.0] {
            rows.push(stubby(s, f).row);
        }
        for ratio in [1e1, 1e2, 1e3] {
            rows.push(short_next_to_long(ratio, f).row);
        }
        rows.push(roll_up(2.25, 32, 20, f).row);
        if long {
            rows.push(roll_up(5.0, 64, 50, f).row);
        }
        rows.push(lee_frame(10, 0.5, 160, f).row);
    }
    rows
}

/// The suite as a Markdown table.
pub fn markdown(rows: &[StressRow]) -> String {
    let mut s = String::from(
        "| case | formulation | converged | increments | iterations (max per increment) | cut-backs | largest residual (increments at round-off) | transfers | contacts (max loaded) | li/l nearest an end | measure | error |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let measure = match &r.measure {
            Some((n, v, refv)) if refv.is_finite() && *refv != 0.0 => {
                format!(
                    "{n}: {v:.6e} (ref {refv:.6e}, rel. err {:.1e})",
                    (v - refv).abs() / refv.abs()
                )
            }
            Some((n, v, _)) => format!("{n}: {v:.4e}"),
            None => String::new(),
        };
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} ({}) | {} | {:.1e} ({}) | {} | {} | {} | {} | {} |\n",
            r.case,
            r.formulation,
            if r.converged { "yes" } else { "**no**" },
            r.increments,
            r.iterations,
            r.max_iterations,
            r.cutbacks,
            r.max_residual,
            r.at_roundoff,
            r.transfers,
            r.max_contacts,
            r.furthest_xi.map(|x| format!("{x:.5}")).unwrap_or_default(),
            measure,
            r.error.clone().unwrap_or_default().replace('|', "/"),
        ));
    }
    s
}
