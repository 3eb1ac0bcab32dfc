//! The observer through which the solver streams iterations, increments and events to the
//! front end, and which stops the run when a newer command is waiting.

use std::collections::VecDeque;
use std::sync::mpsc::{Receiver, SyncSender, TrySendError};

use super::messages::{Command, Message, Repaint};
use crate::solver::report::Flow;
use crate::solver::{Event, IncrementRecord, IterationRecord, Observer};

/// Observer that forwards to the app and stops the run when a newer command is waiting.
pub(super) struct Relay<'a> {
    pub(super) rx: &'a Receiver<Command>,
    pub(super) tx: &'a SyncSender<Message>,
    pub(super) pending: &'a mut VecDeque<Command>,
    pub(super) repaint: &'a Option<Repaint>,
    pub(super) closed: bool,
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

/// Whether a command waiting behind the current work makes the current attempt stale.
pub(super) fn interrupts(c: &Command) -> bool {
    !matches!(
        c,
        Command::Run | Command::RunSteps(_) | Command::Step | Command::Pause
    )
}
