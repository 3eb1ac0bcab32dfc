//! The solver worker thread ("tsm-solver"): owns the `Solver`, takes commands over a channel
//! (load, run, step, drive a prescribed dof to a target, change formulation, reset, cancel)
//! and streams iterations, increments, events and errors back over a bounded channel. Newer
//! commands interrupt stale work through the observer; solver panics are caught and reported.
//! No GUI dependency: the app, the tests and any other front end use it the same way.

use std::collections::VecDeque;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{self, Receiver, Sender, SyncSender, TryRecvError, TrySendError};
use std::thread::JoinHandle;
use std::time::Duration;

use crate::scene::Scene;
use crate::solver::element::beam::BeamElement;
use crate::solver::report::Flow;
use crate::solver::{
    Event, Formulation, IncrementRecord, IterationRecord, Observer, SolveError, Solver,
    StretchCorrection,
};

/// Capacity of the worker's outgoing message channel.
pub const CHANNEL_CAPACITY: usize = 1024;

/// A request to the worker. Commands are handled in order; a command that arrives while the
/// worker is solving interrupts the current Newton attempt unless it is `Run`, `RunSteps`,
/// `Step` or `Pause` (those wait for the current increment to converge).
#[derive(Debug)]
pub enum Command {
    /// Replace the scene and start from its undeformed state.
    LoadScene(Box<Scene>),
    /// Solve the scene's remaining steps (up to `Scene::steps` steps in all).
    Run,
    /// Solve this many more steps.
    RunSteps(usize),
    /// Stop after the increment being solved.
    Pause,
    /// Solve one more step.
    Step,
    /// March prescribed dof `index` from the current equilibrium to `value`, in increments no
    /// larger than that dof's `|per_step|`. A newer target replaces the old one at once.
    SetTarget {
        /// Index into `Model::prescribed`.
        index: usize,
        /// Target value (m or rad).
        value: f64,
    },
    /// Reload the scene with this element formulation.
    SetFormulation(Formulation),
    /// Reload the scene with this stretch-correction mode (`SolverParams::stretch_correction`).
    SetStretchCorrection(StretchCorrection),
    /// Back to the undeformed state of the current scene.
    Reset,
    /// Abandon the current work at once (the last converged state is kept).
    Cancel,
    /// End the thread.
    Shutdown,
}

/// The state right after a scene (re)load.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The scene as solved (its model carries the formulation in use).
    pub scene: Scene,
    /// The element evaluators, needed by `solver::element::shape::element_curve`.
    pub elements: Vec<BeamElement>,
    /// The undeformed state as increment 0 (no forces, no contacts).
    pub initial: IncrementRecord,
    /// "node N v"-style label of every prescribed dof.
    pub prescribed_labels: Vec<String>,
}

/// What the worker reports.
#[derive(Clone, Debug)]
pub enum Message {
    /// A Newton iteration (may be dropped when the channel is full).
    Iteration(IterationRecord),
    /// A converged increment.
    Increment(Box<IncrementRecord>),
    /// A cut-back or contact event.
    Event(Event),
    /// A solver error or a caught panic; the worker stays usable.
    Error(String),
    /// A scene was (re)loaded.
    Loaded(Box<Loaded>),
    /// The worker started solving.
    Busy,
    /// The worker has nothing left to do.
    Idle,
}

/// Called after the worker sends messages (e.g. `egui::Context::request_repaint`).
pub type Repaint = Box<dyn Fn() + Send>;

/// Handle to the worker thread. Dropping it shuts the thread down.
pub struct Worker {
    tx: Sender<Command>,
    rx: Option<Receiver<Message>>,
    handle: Option<JoinHandle<()>>,
}

impl Worker {
    /// Start the thread. `repaint` is called after messages are sent.
    pub fn spawn(repaint: Option<Repaint>) -> Worker {
        let (tx, cmd_rx) = mpsc::channel();
        let (msg_tx, rx) = mpsc::sync_channel(CHANNEL_CAPACITY);
        let handle = std::thread::Builder::new()
            .name("tsm-solver".into())
            .spawn(move || Thread::new(cmd_rx, msg_tx, repaint).run())
            .expect("cannot spawn the solver thread");
        Worker {
            tx,
            rx: Some(rx),
            handle: Some(handle),
        }
    }

    /// Send a command (ignored if the thread has ended).
    pub fn send(&self, command: Command) {
        let _ = self.tx.send(command);
    }

    /// The next message, if one is waiting. Never blocks.
    pub fn try_recv(&self) -> Option<Message> {
        self.rx.as_ref()?.try_recv().ok()
    }

    /// The next message, waiting at most `timeout`.
    pub fn recv_timeout(&self, timeout: Duration) -> Option<Message> {
        self.rx.as_ref()?.recv_timeout(timeout).ok()
    }

    /// Every message waiting now. Never blocks.
    pub fn drain(&self) -> Vec<Message> {
        std::iter::from_fn(|| self.try_recv()).collect()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        let _ = self.tx.send(Command::Shutdown);
        // Dropping the receiver unblocks a worker waiting on a full channel.
        self.rx = None;
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

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
struct Thread {
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

/// Whether a command waiting behind the current work makes the current attempt stale.
fn interrupts(c: &Command) -> bool {
    !matches!(
        c,
        Command::Run | Command::RunSteps(_) | Command::Step | Command::Pause
    )
}

impl Thread {
    fn new(rx: Receiver<Command>, tx: SyncSender<Message>, repaint: Option<Repaint>) -> Thread {
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

    fn run(mut self) {
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
            Ok(Ok(solver)) => {
                let loaded = Loaded {
                    initial: initial_record(&solver),
                    elements: solver.elements().to_vec(),
                    prescribed_labels: scene
                        .model
                        .prescribed
                        .iter()
                        .map(|p| format!("node {} {}", scene.model.nodes[p.node].id, p.dof.name()))
                        .collect(),
                    scene,
                };
                self.solver = Some(solver);
                self.send(Message::Loaded(Box::new(loaded)));
            }
            Ok(Err(e)) => self.send(Message::Error(format!("{}: {e}", scene.file.name))),
            Err(p) => self.send(Message::Error(format!(
                "solver panicked while loading: {}",
                panic_text(&p)
            ))),
        }
        self.go_idle();
    }

    /// One unit of work: one scene step, or one increment towards the targets.
    fn work(&mut self) {
        let Some(mut solver) = self.solver.take() else {
            return self.go_idle();
        };
        let (goal, lambda) = match &self.mode {
            Mode::Running(_) => (
                solver
                    .model
                    .prescribed
                    .iter()
                    .zip(solver.prescribed_values())
                    .map(|(p, v)| v + p.per_step)
                    .collect(),
                solver.load_factor() + solver.model.load_per_step,
            ),
            Mode::Targeting(t) => (t.clone(), solver.load_factor()),
            Mode::Idle => {
                self.solver = Some(solver);
                return;
            }
        };
        // Scene steps of an arc-length scene are arcs: the solver picks the load factor.
        let arc = matches!(self.mode, Mode::Running(_)) && solver.params.arc_length.is_some();
        let next = next_target(&solver, &goal);
        let mut obs = Relay {
            rx: &self.rx,
            tx: &self.tx,
            pending: &mut self.pending,
            repaint: &self.repaint,
            closed: false,
        };
        let result = catch_unwind(AssertUnwindSafe(|| {
            if arc {
                solver.step(&mut obs)
            } else {
                solver.advance_to(&next, lambda, &mut obs)
            }
        }));
        if obs.closed {
            self.alive = false;
        }
        let done = reached(&solver, &goal);
        self.solver = Some(solver);
        match result {
            Ok(Ok(_)) | Ok(Err(SolveError::Stopped)) => {}
            Ok(Err(e)) => {
                self.send(Message::Error(e.to_string()));
                return self.go_idle();
            }
            Err(p) => {
                self.send(Message::Error(format!(
                    "solver panicked: {}",
                    panic_text(&p)
                )));
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

/// Observer that forwards to the app and stops the run when a newer command is waiting.
struct Relay<'a> {
    rx: &'a Receiver<Command>,
    tx: &'a SyncSender<Message>,
    pending: &'a mut VecDeque<Command>,
    repaint: &'a Option<Repaint>,
    closed: bool,
}

impl Relay<'_> {
    fn flow(&mut self) -> Flow {
        while let Ok(c) = self.rx.try_recv() {
            self.pending.push_back(c);
        }
        if self.closed || self.pending.iter().any(interrupts) {
            Flow::Stop
        } else {
            Flow::Continue
        }
    }

    fn send(&mut self, m: Message) {
        if self.tx.send(m).is_err() {
            self.closed = true;
        }
        if let Some(r) = self.repaint {
            r();
        }
    }
}

impl Observer for Relay<'_> {
    fn iteration(&mut self, r: &IterationRecord) -> Flow {
        match self.tx.try_send(Message::Iteration(r.clone())) {
            Ok(()) | Err(TrySendError::Full(_)) => {}
            Err(TrySendError::Disconnected(_)) => self.closed = true,
        }
        if let Some(rp) = self.repaint {
            rp();
        }
        self.flow()
    }
    fn increment(&mut self, r: &IncrementRecord) -> Flow {
        self.send(Message::Increment(Box::new(r.clone())));
        self.flow()
    }
    fn event(&mut self, e: &Event) {
        self.send(Message::Event(e.clone()));
    }
}

/// The next prescribed values on the way to `targets`: the whole way if every dof is within its
/// `|per_step|`, else scaled so that no dof moves more than its `|per_step|`.
pub fn next_target(solver: &Solver, targets: &[f64]) -> Vec<f64> {
    let cur = solver.prescribed_values();
    let mut f = 1.0f64;
    for ((p, c), t) in solver.model.prescribed.iter().zip(cur).zip(targets) {
        let d = (t - c).abs();
        let h = p.per_step.abs();
        if d > h && h > 0.0 {
            f = f.min(h / d);
        }
    }
    if f >= 1.0 {
        return targets.to_vec();
    }
    cur.iter()
        .zip(targets)
        .map(|(c, t)| c + f * (t - c))
        .collect()
}

/// Whether the prescribed values are at the targets (to a negligible fraction of a step).
fn reached(solver: &Solver, targets: &[f64]) -> bool {
    solver
        .model
        .prescribed
        .iter()
        .zip(solver.prescribed_values())
        .zip(targets)
        .all(|((p, c), t)| (t - c).abs() <= 1e-12 * p.per_step.abs().max(t.abs()).max(1e-300))
}

/// The undeformed state of a fresh solver as increment 0.
pub fn initial_record(solver: &Solver) -> IncrementRecord {
    let model = &solver.model;
    IncrementRecord {
        increment: 0,
        prescribed: solver.prescribed_values().to_vec(),
        load_factor: solver.load_factor(),
        iterations: 0,
        iterations_8_orders: None,
        relative_residual: 0.0,
        reference: 0.0,
        roundoff_floor: 0.0,
        status: Default::default(),
        cutbacks: 0,
        residuals: Vec::new(),
        nodes: solver.node_states(solver.displacements()),
        element_forces: vec![[0.0; 3]; model.beams.len()],
        reactions: Vec::new(),
        contacts: Vec::new(),
        max_penetration: 0.0,
        events: Vec::new(),
        seconds: 0.0,
    }
}

fn panic_text(p: &Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}
