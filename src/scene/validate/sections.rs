//! The `sections` of a scene: stiffnesses positive, finite and in range, names unique.

use std::collections::HashMap;

use super::errors::{positive, Ctx, SceneError};
use crate::scene::format::SceneFile;
use crate::solver::Section;

/// The sections of `sf` by name.
pub(super) fn sections<'a>(
    ctx: &Ctx,
    sf: &'a SceneFile,
) -> Result<HashMap<&'a str, Section>, SceneError> {
    let mut sections: HashMap<&str, Section> = HashMap::new();
    for (k, s) in sf.sections.iter().enumerate() {
        let f = |n: &str| format!("sections[{k}].{n} (section \"{}\")", s.name);
        let nd = Some(format!("name:\"{}\"", s.name));
        positive(ctx, f("E"), nd.clone(), s.e)?;
        positive(ctx, f("A"), nd.clone(), s.a)?;
        positive(ctx, f("I"), nd.clone(), s.i)?;
        let nu = s.nu.unwrap_or(0.3);
        if !(nu > -1.0 && nu < 0.5) {
            return Err(ctx.err(
                f("nu"),
                nd,
                format!("Poisson's ratio must lie in (-1, 0.5), got {nu}"),
            ));
        }
        let g = s.g.unwrap_or(s.e / (2.0 * (1.0 + nu)));
        positive(ctx, f("G"), nd.clone(), g)?;
        let ae = s.ae.unwrap_or(s.a);
        positive(ctx, f("Ae"), nd.clone(), ae)?;
        // Each factor may be fine and the stiffness still overflow or underflow.
        for (field, what, v) in [
            ("E", "E A", s.e * s.a),
            ("E", "E I", s.e * s.i),
            ("G", "G Ae", g * ae),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ctx.err(
                    f(field),
                    nd,
                    format!("the stiffness {what} = {v} is out of range (overflows or underflows)"),
                ));
            }
        }
        if sections
            .insert(
                &s.name,
                Section {
                    ea: s.e * s.a,
                    ei: s.e * s.i,
                    gae: g * ae,
                },
            )
            .is_some()
        {
            return Err(ctx.err(f("name"), nd, "duplicate section name"));
        }
    }
    Ok(sections)
}
