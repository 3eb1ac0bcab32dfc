//! The command line: output piped into a reader that stops early (`| head`) ends the program
//! quietly, with exit status 0 and nothing on stderr. The comb prints more than a pipe holds
//! (64 KiB), so the solver is still writing when the pipe closes.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

#[test]
fn solve_piped_into_head_exits_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["solve", "comb"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let mut first = String::new();
    {
        let mut out = BufReader::new(child.stdout.take().expect("stdout"));
        out.read_line(&mut first).expect("a line");
        // `out` dropped here: the pipe closes while the solver still prints.
    }
    let result = child.wait_with_output().expect("exits");
    assert!(first.starts_with("# "), "{first}");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(0), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
