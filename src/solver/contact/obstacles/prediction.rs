//! The obstacle contacts a converged pass, or an iterate near one, predicts from the
//! linearised problem in the space of its candidates ([`ContactSet::predicted_changes`]):
//! the changes of a whole set at once, with the forces its contacts carry, where making and
//! letting go pass by pass would swing between sets.

use nalgebra::{DMatrix, DVector};

use super::node_length;
use crate::solver::assembly::{Assembled, Ordering};
use crate::solver::contact::set::{ContactSet, ContactView};
use crate::solver::linear::{BandMatrix, NOT_FREE};

/// The most rounds of the small active-set iteration of [`ContactSet::predicted_changes`].
const PREDICTION_ROUNDS: usize = 30;

/// A candidate of the prediction: an obstacle contact, or a node found inside its obstacle.
struct Candidate {
    /// Index of its pair in `ObstacleContacts::links`.
    link: usize,
    /// Its gap after the next Newton correction (m).
    gap: f64,
    /// Its spring's force `multiplier - penalty gap` there (N).
    force: f64,
    /// The obstacle's normal at it.
    normal: [f64; 2],
    /// The equations of its node's u and v.
    eqs: [usize; 2],
}

impl ContactSet {
    /// The obstacle contacts the linearised problem holds, found in the space of the
    /// candidates alone, at displacements `d` with assembly `asm` and tangent `tangent` over
    /// the equations of `ord`, where contacts must change (one turned tensile, a node inside its
    /// obstacle). The candidates are the contacts and the nodes found inside their obstacle,
    /// taken where the next Newton correction puts them. The tangent's response to a unit push
    /// along each candidate's normal (a solve each with its factors) gives how every
    /// candidate's gap answers every push; on that small system contacts are made where a gap
    /// would close and let go where a force would turn tensile, round after round, until they
    /// hold. They are then made and let go in the model at once, each contact's multiplier
    /// taking the force it is found to carry (the augmented Lagrangian update, ahead), so that
    /// the next pass of the whole model closes the gaps too. A beam wrapping a drum, whose
    /// wrapped nodes touch with next to no force, finds its contacts so in one pass instead of
    /// swinging between sets, pass after pass. Returns the contacts made or let go; `None`
    /// where the prediction does not apply (friction on an obstacle, a set that came back
    /// within the attempt, nothing to change, a node found too deep) or its rounds do not
    /// settle: the changes are then made one pass at a time (`obstacle_changes`).
    pub(crate) fn predicted_changes(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
        (tangent, ord): (&BandMatrix, &Ordering),
    ) -> Option<usize> {
        let m = &cv.structure.model;
        let frictional = (self.obstacles.links.iter())
            .any(|l| l.grip.is_some() || m.obstacles[l.obstacle].mu > 0.0);
        if frictional || self.obstacles.guard.one_at_a_time() {
            return None;
        }
        let mut cand = self.predicted_candidates(cv, d, asm, ord)?;
        let mut factors = tangent.clone();
        factors.factor(0.0).ok()?;
        let k = cv.structure.obstacle_penalty;
        // Where the next Newton correction takes the candidates.
        let mut step = asm.unbalanced.clone();
        factors.solve(&mut step);
        for x in cand.iter_mut() {
            let moved = x.normal[0] * step[x.eqs[0]] + x.normal[1] * step[x.eqs[1]];
            x.gap += moved;
            x.force -= k * moved;
        }
        let compliance = candidate_compliance(&cand, &factors, ord.n_eq);
        let was: Vec<bool> = (cand.iter())
            .map(|x| self.obstacles.links[x.link].active)
            .collect();
        let (holds, forces) = settle_candidates(
            &cand,
            &compliance,
            &was,
            k,
            cv.structure.obstacle_tolerance(),
        )?;
        let changed = holds.iter().zip(&was).filter(|(a, b)| a != b).count();
        if changed == 0 {
            return None;
        }
        let let_go = &asm.elements.obstacle_forces;
        for (i, x) in cand.iter().enumerate() {
            let link = &mut self.obstacles.links[x.link];
            link.multiplier = if holds[i] { forces[i] } else { 0.0 };
            if holds[i] == was[i] {
                continue;
            }
            link.active = holds[i];
            if holds[i] {
                self.obstacles.touched.push(x.link);
            } else {
                // Let go at no more than no force: it may still press now, relieved by the
                // other changes.
                self.obstacles
                    .let_go
                    .insert(x.link, let_go[x.link].min(0.0));
            }
        }
        let set: Vec<bool> = self.obstacles.links.iter().map(|l| l.active).collect();
        self.obstacles.guard.reached(set);
        Some(changed)
    }

    /// The candidates of `predicted_changes` at displacements `d` (assembly `asm`, equations of
    /// `ord`): every contact and every node inside its obstacle by more than the tolerance, but
    /// for held nodes, whose contacts move nothing. `None` where nothing must change or a node
    /// that did not rest on its obstacle is found deeper than it may be (`obstacle_changes`
    /// then cuts the increment back).
    fn predicted_candidates(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
        ord: &Ordering,
    ) -> Option<Vec<Candidate>> {
        let dofs = &cv.structure.dofs;
        let (k, tol) = (
            cv.structure.obstacle_penalty,
            cv.structure.obstacle_tolerance(),
        );
        let forces = &asm.elements.obstacle_forces;
        let mut out = Vec::new();
        let mut violated = false;
        for (i, link) in self.obstacles.links.iter().enumerate() {
            // Out of its obstacle's reach (an arc's node beyond its angles): a free node is no
            // candidate; a contact there lets go as usual.
            let Some(gap) = cv.obstacle_gap(d, link.node, link.obstacle) else {
                if link.active {
                    return None;
                }
                continue;
            };
            if !link.active && gap.g >= -tol {
                continue;
            }
            let reach = cv.structure.params.max_penetration * node_length(cv, link.node);
            if !link.active && !self.obstacles.resting[i] && -gap.g > reach {
                return None;
            }
            let eqs = [0, 1].map(|o| ord.eq[dofs.dof(link.node, o)]);
            if eqs.contains(&NOT_FREE) {
                continue;
            }
            violated |= !link.active || forces[i] < 0.0;
            out.push(Candidate {
                link: i,
                gap: gap.g,
                force: link.multiplier - k * gap.g,
                normal: gap.n,
                eqs: eqs.map(|e| e as usize),
            });
        }
        (violated && !out.is_empty()).then_some(out)
    }
}

/// How the candidates' gaps answer unit pushes along their normals, by the factored tangent
/// `factors` over `n_eq` equations: entry (a, b) is a's gap under b's push.
fn candidate_compliance(cand: &[Candidate], factors: &BandMatrix, n_eq: usize) -> DMatrix<f64> {
    let c = cand.len();
    let mut out = DMatrix::zeros(c, c);
    let mut push = vec![0.0; n_eq];
    for (b, x) in cand.iter().enumerate() {
        push.fill(0.0);
        push[x.eqs[0]] = x.normal[0];
        push[x.eqs[1]] = x.normal[1];
        factors.solve(&mut push);
        for (a, y) in cand.iter().enumerate() {
            out[(a, b)] = y.normal[0] * push[y.eqs[0]] + y.normal[1] * push[y.eqs[1]];
        }
    }
    out
}

/// The small active-set iteration of `predicted_changes` over candidates `cand` in contact as
/// `was`, with their `compliance`, penalty `k` and gap tolerance `tol`. Each round solves for
/// the extra pushes x on the candidates that turn the model of `was` into the model of the
/// round's set: a contact let go cancels its spring's force (`x - k C x = -F`), a node made a
/// contact gets its spring's (`x + k C x = F`), the others none; then every contact whose
/// force `F - k C x` stays compressive holds, and every other node whose gap `g + C x` is inside
/// by more than `tol` touches. Returns the set that comes back unchanged, with each candidate's
/// force in it; `None` where a set repeats or the rounds run out.
fn settle_candidates(
    cand: &[Candidate],
    compliance: &DMatrix<f64>,
    was: &[bool],
    k: f64,
    tol: f64,
) -> Option<(Vec<bool>, Vec<f64>)> {
    let c = cand.len();
    let mut holds = was.to_vec();
    let mut seen = vec![holds.clone()];
    for _ in 0..PREDICTION_ROUNDS {
        let mut a = DMatrix::<f64>::identity(c, c);
        let mut rhs = DVector::<f64>::zeros(c);
        for i in (0..c).filter(|&i| was[i] != holds[i]) {
            let sign = if holds[i] { 1.0 } else { -1.0 };
            for j in 0..c {
                a[(i, j)] += sign * k * compliance[(i, j)];
            }
            rhs[i] = sign * cand[i].force;
        }
        let moved = compliance * a.lu().solve(&rhs)?;
        let forces: Vec<f64> = (0..c).map(|i| cand[i].force - k * moved[i]).collect();
        let next: Vec<bool> = (0..c)
            .map(|i| match holds[i] {
                true => forces[i] > 0.0,
                false => cand[i].gap + moved[i] < -tol,
            })
            .collect();
        if next == holds {
            return Some((holds, forces));
        }
        if seen.contains(&next) {
            return None;
        }
        seen.push(next.clone());
        holds = next;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn candidate(gap: f64, force: f64) -> Candidate {
        Candidate {
            link: 0,
            gap,
            force,
            normal: [0.0, 1.0],
            eqs: [0, 1],
        }
    }

    /// A node inside by g on a structure of compliance c, made a contact with penalty k: its
    /// spring and the structure, two springs in series, carry k |g| / (1 + k c).
    #[test]
    fn a_node_made_a_contact_carries_the_force_of_two_springs_in_series() {
        let (g, c, k) = (-1e-3, 1e-4, 3e4);
        let cand = [candidate(g, -k * g)];
        let compliance = DMatrix::from_element(1, 1, c);
        let (holds, forces) = settle_candidates(&cand, &compliance, &[false], k, 1e-9).unwrap();
        assert_eq!(holds, vec![true]);
        let series = -k * g / (1.0 + k * c);
        assert!((forces[0] - series).abs() < 1e-12 * series, "{forces:?}");
    }

    /// Two nodes of a structure of compliance S = [[2, 1], [1, 2]] 1e-4 m/N, penalty k = 1e4
    /// N/m: node 0 in contact and pulling with 1 N, node 1 free and 3e-4 m inside. Solved by
    /// hand on the structure alone: letting node 0 go takes its 1 N pull off, and node 1's
    /// spring then carries f1 = k (3e-4 - S10 - S11 f1), f1 = 2/3 N, while node 0's gap opens
    /// by S00 + S01 f1 > 0, so it stays free. The small iteration, given the compliance with
    /// node 0's spring in it (Sherman-Morrison), finds that set and force.
    #[test]
    fn a_pulling_contact_lets_go_and_the_node_it_held_out_touches_as_by_hand() {
        let k = 1e4;
        let s = DMatrix::from_row_slice(2, 2, &[2e-4, 1e-4, 1e-4, 2e-4]);
        // With node 0's spring: C = S - k S e0 e0^T S / (1 + k S00).
        let col = s.column(0).into_owned();
        let compliance = &s - &col * col.transpose() * (k / (1.0 + k * s[(0, 0)]));
        let cand = [candidate(0.0, -1.0), candidate(-3e-4, 3.0)];
        let (holds, forces) =
            settle_candidates(&cand, &compliance, &[true, false], k, 1e-12).unwrap();
        assert_eq!(holds, vec![false, true]);
        assert!((forces[1] - 2.0 / 3.0).abs() < 1e-12, "{forces:?}");
    }
}
