//! The solver thread: owns the `Solver`, handles commands in order, and runs the increments of
//! a run or a drag in small pieces so that a newer command is never kept waiting. Solver
//! panics are caught and reported.

use std::collections::VecDeque;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{Receiver, SyncSender, TryRecvError};
use std::sync::Arc;

use super::messages::{Command, Failure, Loaded, Message, Repaint};
use super::relay::Relay;
use super::targets::{next_target, panic_text, reached, steps_along};
use crate::scene::Scene;
use crate::solver::{SolveError, Solver};

/// What the thread is doing between commands.
#[derive(Clone, Debug, PartialEq)]
enum Mode {
    Idle,
    /// Steps left to solve.
    Running(usize),
    /// Prescribed values to reach.
    Targeting(Vec<f64>),
}

/// The thread's state.
pub(super) struct Thread {
    rx: Receiver<Command>,
    tx: SyncSender<Message>,
    repaint: Option<Repaint>,
    pending: VecDeque<Command>,
    scene: Option<Scene>,
    solver: Option<Solver>,
    mode: Mode,
    steps_done: usize,
    alive: bool,
}

impl Thread {
    pub(super) fn new(
        rx: Receiver<Command>,
        tx: SyncSender<Message>,
        repaint: Option<Repaint>,
    ) -> Thread {
        Thread {
            rx,
            tx,
            repaint,
            pending: VecDeque::new(),
            scene: None,
            solver: None,
            mode: Mode::Idle,
            steps_done: 0,
            alive: true,
        }
    }

    pub(super) fn run(mut self) {
        while self.alive {
            if self.pending.is_empty() {
                if self.mode == Mode::Idle {
                    match self.rx.recv() {
                        Ok(c) => self.pending.push_back(c),
                        Err(_) => return,
                    }
                }
                loop {
                    match self.rx.try_recv() {
                        Ok(c) => self.pending.push_back(c),
                        Err(TryRecvError::Empty) => break,
                        Err(TryRecvError::Disconnected) => {
                            self.alive = false;
                            break;
                        }
                    }
                }
            }
            while let Some(c) = self.pending.pop_front() {
                self.handle(c);
                if !self.alive {
                    return;
                }
            }
            if self.mode != Mode::Idle {
                self.work();
            }
        }
    }

    /// Send a message that must arrive; a closed channel ends the thread.
    fn send(&mut self, m: Message) {
        if self.tx.send(m).is_err() {
            self.alive = false;
        }
        self.poke();
    }

    fn poke(&self) {
        if let Some(r) = &self.repaint {
            r();
        }
    }

    fn go_idle(&mut self) {
        self.mode = Mode::Idle;
        self.send(Message::Idle);
    }

    fn handle(&mut self, c: Command) {
        match c {
            Command::LoadScene(scene) => {
                self.scene = Some(*scene);
                self.reload();
            }
            Command::SetFormulation(f) => {
                if let Some(s) = &mut self.scene {
                    s.model.formulation = f;
                }
                self.reload();
            }
            Command::SetStretchCorrection(m) => {
                if let Some(s) = &mut self.scene {
                    s.params.stretch_correction = m;
                }
                self.reload();
            }
            Command::Reset => self.reload(),
            Command::Restore(checkpoint) => {
                self.mode = Mode::Idle;
                if let (Some(solver), Some(scene)) = (&mut self.solver, &self.scene) {
                    solver.restore(&checkpoint);
                    self.steps_done = steps_along(solver, scene.steps);
                    self.send(Message::Restored(checkpoint.increment()));
                }
                self.go_idle();
            }
            Command::Run => {
                let total = self.scene.as_ref().map_or(0, |s| s.steps);
                self.start(Mode::Running(total.saturating_sub(self.steps_done)));
            }
            Command::RunSteps(n) => self.start(Mode::Running(n)),
            Command::Step => match self.mode {
                Mode::Running(n) => self.mode = Mode::Running(n + 1),
                _ => self.start(Mode::Running(1)),
            },
            Command::SetTarget { index, value } => {
                let Some(solver) = &self.solver else {
                    return self.go_idle();
                };
                let mut targets = match &self.mode {
                    Mode::Targeting(t) => t.clone(),
                    _ => solver.prescribed_values().to_vec(),
                };
                if index < targets.len() && value.is_finite() {
                    targets[index] = value;
                }
                self.start(Mode::Targeting(targets));
            }
            Command::Pause | Command::Cancel => self.go_idle(),
            Command::Shutdown => self.alive = false,
        }
    }

    /// Enter a working mode (or report idle straight away if there is nothing to do).
    fn start(&mut self, mode: Mode) {
        if self.solver.is_none() || mode == Mode::Running(0) {
            return self.go_idle();
        }
        if self.mode == Mode::Idle {
            self.send(Message::Busy);
        }
        self.mode = mode;
    }

    /// Rebuild the solver from the scene and report the initial state.
    fn reload(&mut self) {
        self.mode = Mode::Idle;
        self.steps_done = 0;
        self.solver = None;
        let Some(scene) = self.scene.clone() else {
            return self.go_idle();
        };
        match catch_unwind(AssertUnwindSafe(|| scene.solver())) {
            Ok(Ok(mut solver)) => {
                solver.keep_checkpoints(true);
                let loaded = Loaded::new(scene, &solver);
                self.solver = Some(solver);
                self.send(Message::Loaded(Box::new(loaded)));
            }
            Ok(Err(e)) => self.send(Message::Error(format!("{}: {e}", scene.file.name).into())),
            Err(p) => self.send(Message::Error(
                format!("solver panicked while loading: {}", panic_text(&p)).into(),
            )),
        }
        self.go_idle();
    }

    /// One unit of work: one scene step, or one increment towards the targets.
    fn work(&mut self) {
        let Some(mut solver) = self.solver.take() else {
            return self.go_idle();
        };
        let (goal, factors) = match &self.mode {
            Mode::Running(_) => match solver.step_targets() {
                Some(t) => t,
                // Past the end of the load path: nothing left to run.
                None => {
                    self.solver = Some(solver);
                    return self.go_idle();
                }
            },
            Mode::Targeting(t) => (t.clone(), solver.load_factors().to_vec()),
            Mode::Idle => {
                self.solver = Some(solver);
                return;
            }
        };
        // Scene steps of an arc-length scene are arcs (the solver picks the load factor), and
        // those of a load path are its points, each in its stage: the solver takes them whole.
        let running = matches!(self.mode, Mode::Running(_));
        let staged = running && solver.structure.model.path.is_some();
        let by_step = staged || (running && solver.structure.params.arc_length.is_some());
        let path_before = solver.path_step();
        let next = next_target(&solver, &goal);
        let mut obs = Relay {
            rx: &self.rx,
            tx: &self.tx,
            pending: &mut self.pending,
            repaint: &self.repaint,
            closed: false,
        };
        let result = catch_unwind(AssertUnwindSafe(|| {
            if by_step {
                solver.step(&mut obs)
            } else {
                solver.advance_to(&next, &factors, &mut obs)
            }
        }));
        if obs.closed {
            self.alive = false;
        }
        let done = if staged {
            solver.path_step() > path_before
        } else {
            reached(&solver, &goal)
        };
        let kept = solver.take_checkpoints();
        self.solver = Some(solver);
        for c in kept {
            self.send(Message::Checkpoint(Arc::new(c)));
        }
        match result {
            Ok(Ok(_)) | Ok(Err(SolveError::Stopped)) => {}
            Ok(Err(e)) => {
                self.send(Message::Error(Failure::Solve(e)));
                return self.go_idle();
            }
            Err(p) => {
                let why = format!("solver panicked: {}", panic_text(&p));
                self.send(Message::Error(why.into()));
                return self.go_idle();
            }
        }
        match self.mode {
            Mode::Running(n) if done => {
                self.steps_done += 1;
                if n <= 1 {
                    self.go_idle();
                } else {
                    self.mode = Mode::Running(n - 1);
                }
            }
            Mode::Targeting(_) if done => self.go_idle(),
            _ => {}
        }
    }
}
