//! Committing an accepted attempt: it becomes the converged state (sides remembered, the
//! crossing check moved on, the assembly kept for the next predictor), and its increment
//! record is written (node states, element forces, reactions, contacts).

use super::solver::Solver;
use crate::solver::assembly::Assembled;
use crate::solver::model::Dof;
use crate::solver::newton::Converged;
use crate::solver::report::{
    Flow, IncrementRecord, IncrementStatus, NodeState, Observer, Reaction,
};

impl Solver {
    /// Commit an accepted attempt (`commit`), keep its checkpoint, and give its events and
    /// record to `obs`: the record and whether `obs` asks to stop.
    pub(crate) fn publish(
        &mut self,
        c: Converged,
        checked: (IncrementStatus, Vec<NodeState>),
        targets: (Vec<f64>, bool),
        cutbacks: usize,
        seconds: f64,
        obs: &mut dyn Observer,
    ) -> (IncrementRecord, Flow) {
        let rec = self.commit(c, checked, targets, cutbacks, seconds);
        self.keep_checkpoint();
        for e in &rec.events {
            obs.event(e);
        }
        let flow = obs.increment(&rec);
        (rec, flow)
    }

    /// Make an accepted attempt (`acceptance` gave `checked`) the converged state, and its
    /// record.
    pub(crate) fn commit(
        &mut self,
        c: Converged,
        checked: (IncrementStatus, Vec<NodeState>),
        (tp, partial): (Vec<f64>, bool),
        cutbacks: usize,
        seconds: f64,
    ) -> IncrementRecord {
        self.state.increment += 1;
        self.work.spare.get_mut().d = std::mem::replace(&mut self.state.d, c.d);
        self.state.residue = c.residue;
        self.state.contacts = c.contacts;
        self.state.prescribed = tp;
        self.state.load_factors = c.load_factors;
        let max_penetration = c.max_penetration;
        let mut contacts = std::mem::take(&mut self.state.contacts);
        contacts.remember_sides(&self.view(), &self.state.d);
        self.state.contacts = contacts;
        let (status, nodes) = checked;
        if !self.crossing.is_empty() {
            let active = self.state.contacts.pairs();
            self.crossing
                .accept(&self.structure.model, nodes.clone(), &active);
        }
        let fext = self.structure.external_force(&self.state.load_factors);
        let reactions = self
            .structure
            .dofs
            .held
            .iter()
            .zip(&c.assembled.held_internal)
            .map(|(&g, i)| {
                let (n, o) = self.structure.dofs.owner(g);
                Reaction {
                    node: self.structure.model.nodes[n].id,
                    dof: Dof::ALL[o].name().to_string(),
                    value: i - fext.at(g),
                }
            })
            .collect();
        let contacts = self.state.contacts.states(&self.view(), &c.assembled);
        let obstacle_contacts =
            (self.state.contacts).obstacle_states(&self.view(), &self.state.d, &c.assembled);
        let Assembled {
            unbalanced,
            unbalanced_norm2,
            unloaded,
            held_internal,
            tangent,
            elements,
            ..
        } = c.assembled;
        self.work.converged_assembly.keep(
            self.state.increment,
            Assembled {
                unbalanced,
                unbalanced_norm2,
                unloaded,
                held_internal,
                tangent,
                coupling: Vec::new(),
                elements: Default::default(),
            },
        );
        IncrementRecord {
            increment: self.state.increment,
            prescribed: self.state.prescribed.clone(),
            load_factor: self.state.load_factors[0],
            load_factors: if self.structure.model.load_groups.len() > 1 {
                self.state.load_factors.clone()
            } else {
                Vec::new()
            },
            stage: self.marching,
            partial,
            iterations: c.iterations,
            iterations_8_orders: c.iterations_8_orders,
            relative_residual: c.relative_residual,
            reference: c.reference,
            roundoff_floor: c.roundoff_floor,
            status,
            cutbacks,
            residuals: c.residuals,
            nodes,
            element_forces: elements.beam_forces,
            reactions,
            contacts,
            obstacle_contacts,
            max_penetration,
            events: c.events,
            seconds,
        }
    }
}
