//! Unit tests of the assembly: against the separate passes and the plain loops it replaces
//! with faster equivalents, bit for bit.

use super::assemble::*;
use super::coordinates::add_carried;
use crate::solver::linear::reduce::sum_squares;
use crate::solver::linear::NOT_FREE;

/// `add_scaled` adds what the equation-by-equation loop of `add_carried` over `dof_of` adds
/// (displacements and residues), bit for bit,
/// both where the dofs are in a row (the Mattiasson cantilever: clamped at its first node)
/// and where they are not (Example 3.2: bodies, supports at both ends, contacts).
#[test]
fn a_scaled_correction_lands_on_the_dofs_of_its_equations() {
    for (scene, steps, in_a_row) in [("mattiasson", 0, true), ("example_3_2", 30, false)] {
        let s = crate::test_support::solver_after(scene, steps);
        let ord = s.newton().ordering_for(&s.state.contacts);
        assert_eq!(ord.dofs_in_a_row.is_some(), in_a_row, "{scene}");
        let x: Vec<f64> = (0..ord.n_eq).map(|e| 0.37 * e as f64 - 1.1).collect();
        let d0: Vec<f64> = (0..s.structure.dofs.len())
            .map(|g| (g as f64).sin())
            .collect();
        let (mut expected, mut expected_residue) = (d0.clone(), vec![0.0; d0.len()]);
        for (e, &g) in ord.dof_of.iter().enumerate() {
            let g = g as usize;
            add_carried(&mut expected[g], &mut expected_residue[g], 0.7 * x[e]);
        }
        let (mut d, mut residue) = (d0, vec![0.0; expected.len()]);
        ord.add_scaled((&mut d, &mut residue), 0.7, &x);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&d), bits(&expected), "{scene}");
        assert_eq!(bits(&residue), bits(&expected_residue), "{scene}");
    }
}

/// An assembly into the buffers of an earlier one (stale internal forces and band, zeroed
/// as the elements reach them) gives what an assembly into fresh buffers gives, bit for
/// bit: over the buffers of another state of the same model (a long beam of 1000 elements,
/// several blocks of lazy zeroing; Example 3.2 with contacts, its equations reached out of
/// order) and over those of a larger model.
#[test]
fn an_assembly_over_old_buffers_is_a_fresh_one() {
    let long = crate::scene::builtin::long_beam(1000)
        .solver()
        .expect("stable");
    let mut larger = Assembled::default();
    let ord = long.newton().ordering_for(&long.state.contacts);
    let bent: Vec<f64> = (0..long.state.d.len())
        .map(|g| 1e-3 * (g as f64).sin())
        .collect();
    assemble_into(
        &long.structure.context(&ord),
        &bent,
        true,
        None,
        &mut larger,
    );
    let contact = crate::test_support::solver_after("example_3_2", 30);
    for (s, reuse_larger) in [(&long, false), (&contact, false), (&contact, true)] {
        let ord = s.newton().ordering_for(&s.state.contacts);
        let ctx = s.structure.context(&ord);
        let mut out = if reuse_larger {
            larger.clone()
        } else {
            let other: Vec<f64> = s.state.d.iter().map(|v| 1.5 * v + 1e-4).collect();
            assemble(&ctx, &other, true, None)
        };
        // A deformed state (the long beam has not been stepped).
        let now: Vec<f64> = (s.state.d.iter().enumerate())
            .map(|(g, v)| v + 1e-4 * (0.3 * g as f64).cos())
            .collect();
        assemble_into(&ctx, &now, true, None, &mut out);
        let fresh = assemble(&ctx, &now, true, None);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let case = format!(
            "{} equations, over a larger model's: {reuse_larger}",
            ord.n_eq
        );
        assert_eq!(bits(&out.unbalanced), bits(&fresh.unbalanced), "{case}");
        assert_eq!(
            bits(&out.held_internal),
            bits(&fresh.held_internal),
            "{case}"
        );
        assert!(fresh.unbalanced.iter().any(|f| *f != 0.0), "{case}: loaded");
        let (ko, kf) = (
            out.tangent.expect("tangent"),
            fresh.tangent.expect("tangent"),
        );
        for i in 0..ord.n_eq {
            for j in i.saturating_sub(ord.band)..(i + ord.band + 1).min(ord.n_eq) {
                assert_eq!(ko.get(i, j).to_bits(), kf.get(i, j).to_bits(), "{case}");
            }
        }
    }
}

/// The unbalanced force settled block by block during the assembly is, bit for bit, what
/// separate passes over the internal forces give (negate them, add the loads, then
/// `sum_squares`, as Newton did before): on a chain of 1000 elements (equations in a row,
/// settled as the elements go) and on Example 3.2 with contacts (equations reached out of
/// order, most settled at the end), with the scene's own loads (none for Example 3.2) and with loads at the first
/// equation, on both sides of a block boundary, in the middle and in the last,
/// incomplete block. `reload` then gives what an assembly with the other loads gives.
#[test]
fn the_unbalanced_force_settled_during_assembly_is_the_separate_pass() {
    let long = crate::scene::builtin::long_beam(1002)
        .solver()
        .expect("stable");
    let contact = crate::test_support::solver_after("example_3_2", 30);
    for s in [&long, &contact] {
        let ord = s.newton().ordering_for(&s.state.contacts);
        let n = ord.n_eq;
        assert!(
            n % 4 != 0,
            "{n} equations: the last block must be incomplete"
        );
        let now: Vec<f64> = (s.state.d.iter().enumerate())
            .map(|(g, v)| v + 1e-4 * (0.3 * g as f64).cos())
            .collect();
        let bare = assemble(&s.structure.context(&ord), &now, true, None);
        let internal: Vec<f64> = bare.unbalanced.iter().map(|u| -u).collect();
        assert_eq!(
            bare.unbalanced_norm2.to_bits(),
            sum_squares(&bare.unbalanced).to_bits()
        );
        let scene = crate::solver::newton::Newton::loads_at_equations(
            &s.structure.external_force(&[1.0]),
            &ord,
        );
        let mut spread: Vec<(usize, f64)> = [0, 3, 4, n / 2, n - 2, n - 1]
            .iter()
            .map(|&k| (k, 0.25 + k as f64))
            .collect();
        spread.dedup_by_key(|l| l.0);
        let mut last: Option<Assembled> = None;
        // The long beam is loaded; Example 3.2 is driven by a prescribed displacement.
        assert_eq!(scene.is_empty(), s.structure.model.beams.len() != 1002);
        for loads in [&scene, &spread] {
            let ctx = AssemblyContext {
                loads,
                ..s.structure.context(&ord)
            };
            let asm = assemble(&ctx, &now, true, None);
            let mut expected: Vec<f64> = internal.iter().map(|i| -i).collect();
            for &(k, f) in loads.iter() {
                expected[k] += f;
            }
            let norm2 = sum_squares(&expected);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&asm.unbalanced), bits(&expected), "{n} equations");
            assert_eq!(asm.unbalanced_norm2.to_bits(), norm2.to_bits());
            if let Some(mut other) = last.take() {
                other.reload(loads);
                assert_eq!(bits(&other.unbalanced), bits(&expected), "reloaded");
                assert_eq!(other.unbalanced_norm2.to_bits(), norm2.to_bits());
            }
            last = Some(asm);
        }
    }
}

/// [`Ordering::final_before`] is the smallest equation any beam from e on reaches, its
/// contact nodes included (found here by looking at every later beam): on a chain and on
/// Example 3.2 with contacts.
#[test]
fn no_beam_reaches_below_its_final_equation() {
    for (scene, steps) in [("mattiasson", 0), ("example_3_2", 30)] {
        let s = crate::test_support::solver_after(scene, steps);
        let ord = s.newton().ordering_for(&s.state.contacts);
        assert!(!ord.links.is_empty() || scene == "mattiasson");
        let reach = |e: usize| -> Vec<u32> {
            let b = &s.structure.model.beams[e];
            let mut nodes = vec![b.i, b.j];
            nodes.extend(ord.on_beam[e].iter().map(|&k| ord.links[k].node));
            (nodes.iter())
                .flat_map(|&n| (0..s.structure.model.node_dofs(n)).map(move |o| (n, o)))
                .map(|(n, o)| ord.eq[s.structure.dofs.dof(n, o)])
                .filter(|&q| q != NOT_FREE)
                .collect()
        };
        let nb = s.structure.model.beams.len();
        assert_eq!(ord.final_before.len(), nb + 1);
        assert_eq!(ord.final_before[nb] as usize, ord.n_eq);
        for e in 0..nb {
            let lowest = (e..nb).flat_map(reach).min().unwrap_or(ord.n_eq as u32);
            assert_eq!(ord.final_before[e], lowest, "{scene}: beam {e}");
        }
    }
}

/// The AVX2 build of the assembly (four plain beams at a time) gives the baseline build's
/// internal forces, reactions, tangent and K_fp dp bit for bit (the element arithmetic is
/// the same, only its instructions differ): at a deformed state of the Mattiasson
/// cantilever (a chain, every group of four plain) and of Example 3.2 with contacts on
/// (plain beams between contact beams) under a prescribed increment. Skipped (with a note)
/// without AVX2.
#[test]
fn avx2_build_assembles_bit_for_bit_like_the_baseline() {
    #[cfg(target_arch = "x86_64")]
    {
        let Some(cpu) = crate::test_support::avx2() else {
            return;
        };
        for (scene, steps, turned) in [
            ("mattiasson", 4, false),
            ("mattiasson", 4, true),
            ("example_3_2", 30, false),
        ] {
            let mut s = crate::test_support::solver_after(scene, steps);
            if turned {
                // Nodes 8 to 11 turned a whole turn more: their elements' chord rotations
                // are unwrapped by the scalar path (the lanes hand their groups back).
                for n in 8..12 {
                    let at = s.structure.dofs.first[n] + 2;
                    s.state.d[at] += std::f64::consts::TAU;
                }
                let ends: [_; 4] =
                    std::array::from_fn(|k| s.structure.packed[8 + k].ends(&s.state.d, &[]));
                let c = std::array::from_fn(|k| &s.structure.packed[8 + k].constants);
                let lanes = crate::solver::element::beam_lanes::evaluate4(cpu, c, ends);
                assert!(lanes.is_none(), "handed back");
            }
            let ord = s.newton().ordering_for(&s.state.contacts);
            let ctx = s.structure.context(&ord);
            let dp: Vec<f64> = (0..s.structure.model.prescribed.len())
                .map(|p| 1e-3 * (p + 1) as f64)
                .collect();
            let dp = (!dp.is_empty()).then_some(dp.as_slice());
            let (mut base, mut wide) = (Assembled::default(), Assembled::default());
            assemble_kernel(&ctx, &s.state.d, true, dp, &mut base, None);
            cpu.run(
                #[inline(always)]
                || assemble_kernel(&ctx, &s.state.d, true, dp, &mut wide, Some(cpu)),
            );
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&base.unbalanced), bits(&wide.unbalanced), "{scene}");
            assert_eq!(bits(&base.held_internal), bits(&wide.held_internal));
            assert_eq!(bits(&base.coupling), bits(&wide.coupling), "{scene}");
            let forces = |a: &Assembled| bits(a.elements.beam_forces.concat().as_slice());
            assert_eq!(forces(&base), forces(&wide), "{scene}");
            let all = base.unbalanced.iter().chain(&base.held_internal);
            let biggest = all.fold(0.0f64, |m, f| m.max(f.abs()));
            assert!(biggest > 1e-6, "{scene}: a loaded state ({biggest})");
            if scene == "example_3_2" {
                assert!(!ord.contact_beams.is_empty(), "contacts on");
                assert!(base.coupling.iter().any(|&f| f != 0.0), "K_fp dp");
            }
            let (kb, kw) = (
                base.tangent.expect("tangent"),
                wide.tangent.expect("tangent"),
            );
            for i in 0..ord.n_eq {
                for j in i.saturating_sub(ord.band)..(i + ord.band + 1).min(ord.n_eq) {
                    let (a, b) = (kb.get(i, j), kw.get(i, j));
                    assert_eq!(a.to_bits(), b.to_bits(), "{scene} ({i}, {j})");
                }
            }
        }
    }
}
