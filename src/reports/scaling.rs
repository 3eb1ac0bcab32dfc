//! Scaling report: one Newton increment of a long beam on rollers, loaded in every span, of 10
//! to 10^5 elements of 1 m, in plain Newton iterations, timed in release builds (median of
//! repeats), as time per element per iteration, with the process's peak resident memory after
//! each size (Linux `VmHWM`), beside the yardstick: one iteration of a plain banded assemble-and-factor loop over a chain
//! of as many elements.

use crate::reports::plain_chain::PlainChain;
use crate::reports::work_precision::timed_on;
use crate::scene::builtin::long_beam;
use crate::solver::{Flow, IterationRecord, Observer, StretchCorrection};

/// Counts every Newton iteration, failed attempts included.
struct Count(usize);

impl Observer for Count {
    fn iteration(&mut self, _r: &IterationRecord) -> Flow {
        self.0 += 1;
        Flow::Continue
    }
}

/// One size of the report.
#[derive(Clone, Debug)]
pub struct ScaleRow {
    /// Beam elements.
    pub elements: usize,
    /// Newton iterations of the increment (failed attempts included).
    pub iterations: usize,
    /// Median wall time of the increment (s).
    pub seconds: f64,
    /// Median time per element per iteration (microseconds).
    pub per_element_iteration_us: f64,
    /// The same for the plain chain loop (`plain_chain`), the yardstick (microseconds).
    pub plain_loop_us: f64,
    /// Peak resident memory of the process so far (MiB), if known.
    pub peak_mib: Option<f64>,
}

/// Peak resident set size of this process (MiB), from /proc/self/status.
pub fn peak_memory_mib() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Run the sizes (ascending, so the peak memory belongs to the largest so far).
pub fn measure(sizes: &[usize]) -> Vec<ScaleRow> {
    sizes
        .iter()
        .map(|&n| {
            // The plain Newton iteration, whose cost per element the report measures beside
            // the plain loop's: no stretch correction before a cut-back (the default corrects
            // this beam's turned chords: 2 iterations where plain Newton takes 4 on 10^3
            // elements or more, each with one more band solve).
            let mut sc = long_beam(n);
            sc.params.stretch_correction = StretchCorrection::AfterCutBack;
            // A typical increment: the second (the first also sets up the contact sides, and
            // has no converged state before it to start from).
            let mut fresh = sc.solver().expect("stable");
            fresh
                .step(&mut Count(0))
                .expect("the first increment converges");
            let repeats = if n >= 100_000 {
                3
            } else if n >= 10_000 {
                5
            } else {
                11
            };
            let (seconds, iterations) = timed_on(
                repeats,
                || fresh.clone(),
                |mut s| {
                    let mut count = Count(0);
                    s.step(&mut count).expect("the increment converges");
                    count.0
                },
            );
            let mut chain = PlainChain::with_amplitude(n, 1e-3);
            let (plain, _) = timed_on(repeats, || (), |()| chain.iteration());
            ScaleRow {
                elements: n,
                iterations,
                seconds,
                per_element_iteration_us: seconds * 1e6 / (n * iterations.max(1)) as f64,
                plain_loop_us: plain * 1e6 / n as f64,
                peak_mib: peak_memory_mib(),
            }
        })
        .collect()
}

/// The report as a Markdown table.
pub fn table(rows: &[ScaleRow]) -> String {
    let mut s = String::from(
        "| elements | iterations | increment (ms, median) | per element per iteration (us) | plain loop (us) | peak memory (MiB) |\n|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {:.3} | {:.3} | {:.3} | {} |\n",
            r.elements,
            r.iterations,
            r.seconds * 1e3,
            r.per_element_iteration_us,
            r.plain_loop_us,
            r.peak_mib.map(|m| format!("{m:.0}")).unwrap_or_default()
        ));
    }
    s
}
