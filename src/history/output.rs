//! Output files written whole or not at all: what may be written (`output_problem`), and a
//! temporary file beside the target under a fresh, unpredictable name, created exclusively (an
//! existing file or link there is never written through), renamed over the target only when
//! complete and removed otherwise (`TempFile`, `write_atomic`). Two runs writing one target
//! at once each write their own temporary file: the target is always one of them, whole.

use std::fs::{File, OpenOptions};
use std::hash::{BuildHasher, Hasher};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Why `path` may not be written as an output, if it may not: it is (or links to) one of
/// `inputs`, is a symbolic link (refused rather than followed or replaced), is not a regular
/// file (a folder, a FIFO, a device), or its folder does not exist. Checked before a run, so that
/// a long solve does not end in "cannot write".
pub fn output_problem(path: &Path, inputs: &[&Path]) -> Option<String> {
    if let Ok(meta) = std::fs::symlink_metadata(path) {
        if meta.file_type().is_symlink() {
            return Some("it is a symbolic link: name the file itself".into());
        }
        if !meta.is_file() {
            return Some("it is not a regular file (a folder, a FIFO or a device)".into());
        }
        let same = |input: &Path| match (std::fs::canonicalize(path), std::fs::canonicalize(input))
        {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if inputs.iter().any(|i| same(i)) {
            return Some("it is the input scene, which writing there would overwrite".into());
        }
    }
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Some(format!("its folder {} does not exist", folder.display()));
    }
    None
}

/// A temporary file being written beside its target: renamed over the target by `commit`,
/// removed if dropped before.
pub struct TempFile {
    file: File,
    tmp: PathBuf,
    path: PathBuf,
    committed: bool,
}

/// How many fresh names this process has drawn (part of the next one).
static DRAWN: AtomicU64 = AtomicU64::new(0);

/// A fresh name beside `path`: `.NAME.XXXXXXXXXXXXXXXX.tmp`, the digits drawn from a randomly
/// keyed hash of the process, the time and a counter, so that no other process can tell it
/// in advance.
fn fresh_name(path: &Path) -> PathBuf {
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(DRAWN.fetch_add(1, Ordering::Relaxed));
    h.write_u32(std::process::id());
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH);
    h.write_u128(now.map_or(0, |d| d.as_nanos()));
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{:016x}.tmp", h.finish()))
}

impl TempFile {
    /// A new temporary file for `path`, which `output_problem` must allow: created under a
    /// fresh name, never over an existing file or through a link.
    pub fn create(path: &Path) -> std::io::Result<TempFile> {
        if let Some(why) = output_problem(path, &[]) {
            return Err(std::io::Error::other(why));
        }
        let mut last = None;
        for _ in 0..16 {
            let tmp = fresh_name(path);
            match OpenOptions::new().write(true).create_new(true).open(&tmp) {
                Ok(file) => {
                    return Ok(TempFile {
                        file,
                        tmp,
                        path: path.to_path_buf(),
                        committed: false,
                    })
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
                Err(e) => return Err(e),
            }
        }
        Err(last.unwrap_or_else(|| std::io::Error::other("no fresh temporary name")))
    }

    /// The file to write to.
    pub fn file(&mut self) -> &mut File {
        &mut self.file
    }

    /// Flush the file to disk and move it over the target. The target is checked again, so
    /// that a link or a folder put there during the run is not replaced.
    pub fn commit(mut self) -> std::io::Result<()> {
        self.file.flush()?;
        self.file.sync_all()?;
        if let Some(why) = output_problem(&self.path, &[]) {
            return Err(std::io::Error::other(why));
        }
        std::fs::rename(&self.tmp, &self.path)?;
        self.committed = true;
        Ok(())
    }
}

impl Write for TempFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Write a file whole or not at all: a temporary file beside it (`TempFile`), then a rename.
/// Refuses what `output_problem` refuses; on any failure the temporary file is removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = TempFile::create(path)?;
    tmp.file().write_all(bytes)?;
    tmp.commit()
}
