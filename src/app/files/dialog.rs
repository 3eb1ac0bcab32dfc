//! The native file dialogs (Open, Save scene as, the folder and name of exports), each run on
//! a thread of its own so that the window keeps drawing while one is open; the answer is
//! picked up by [`Dialogs::poll`] on a later frame. Where no dialog can be shown (no desktop
//! portal), the dialog answers nothing and the path fields of the toolbar remain.

use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

/// What a dialog was opened for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// Open a scene file.
    OpenScene,
    /// Save the current scene as a file.
    SaveScene,
    /// Pick the folder and file name (without extension) of the exports.
    ExportStem,
}

/// The dialog in progress, if any.
#[derive(Default)]
pub struct Dialogs {
    pending: Option<(Purpose, Receiver<Option<PathBuf>>, Instant)>,
    shown: usize,
}

/// A dialog that answers "nothing" sooner than this was most likely never shown (a person takes
/// longer to cancel one).
const TOO_QUICK: Duration = Duration::from_millis(300);

/// The answer of a closed dialog.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Answer {
    /// The path chosen.
    Chosen(PathBuf),
    /// Cancelled.
    Cancelled,
    /// No dialog could be shown (no desktop portal, no zenity).
    Unavailable,
}

impl Dialogs {
    /// Whether a dialog is open.
    pub fn open(&self) -> bool {
        self.pending.is_some()
    }

    /// How many dialogs were shown.
    pub fn shown(&self) -> usize {
        self.shown
    }

    /// Show the dialog for `purpose` starting in `folder` (nothing if one is open already).
    pub fn show(&mut self, purpose: Purpose, folder: Option<PathBuf>, repaint: egui::Context) {
        if self.pending.is_some() {
            return;
        }
        let (tx, rx) = channel();
        let spawned = std::thread::Builder::new()
            .name("tsm-file-dialog".into())
            .spawn(move || {
                let mut d = rfd::FileDialog::new();
                if let Some(f) = folder.filter(|f| f.is_dir()) {
                    d = d.set_directory(f);
                }
                let path = match purpose {
                    Purpose::OpenScene => d
                        .set_title("Open a scene")
                        .add_filter("scene", &["ron"])
                        .pick_file(),
                    Purpose::SaveScene => d
                        .set_title("Save the scene as")
                        .add_filter("scene", &["ron"])
                        .set_file_name("scene.ron")
                        .save_file(),
                    Purpose::ExportStem => d
                        .set_title("Export to (the extension is added)")
                        .set_file_name("tsm-history")
                        .save_file(),
                };
                let _ = tx.send(path);
                repaint.request_repaint();
            });
        if spawned.is_ok() {
            self.pending = Some((purpose, rx, Instant::now()));
            self.shown += 1;
        }
    }

    /// The answer of the dialog, once it is closed, with its purpose.
    pub fn poll(&mut self) -> Option<(Purpose, Answer)> {
        let (purpose, rx, shown) = self.pending.as_ref()?;
        let answer = match rx.try_recv() {
            Ok(Some(path)) => Answer::Chosen(path),
            Ok(None) | Err(std::sync::mpsc::TryRecvError::Disconnected)
                if shown.elapsed() < TOO_QUICK =>
            {
                Answer::Unavailable
            }
            Ok(None) | Err(std::sync::mpsc::TryRecvError::Disconnected) => Answer::Cancelled,
            Err(std::sync::mpsc::TryRecvError::Empty) => return None,
        };
        let purpose = *purpose;
        self.pending = None;
        Some((purpose, answer))
    }
}
