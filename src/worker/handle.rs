//! The handle the front end holds: it starts the solver thread, sends it commands, receives
//! its messages without blocking, and shuts the thread down when dropped.

use std::sync::mpsc::{self, Receiver, Sender};
use std::thread::JoinHandle;
use std::time::Duration;

use super::messages::{Command, Message, Repaint, CHANNEL_CAPACITY};
use super::thread::Thread;

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
