//! Frame-time logging for performance checks: with `TSM_FRAME_LOG=1` the app prints, every two
//! seconds, the frame interval and the time spent building the ui, split by whether the worker
//! was solving, and the number of converged increments held.

use std::time::{Duration, Instant};

/// Accumulated frame statistics.
pub struct FrameLog {
    last: Option<Instant>,
    window: Instant,
    frames: u32,
    busy_frames: u32,
    intervals: u32,
    interval_sum: Duration,
    interval_max: Duration,
    build_sum: Duration,
    build_max: Duration,
}

impl FrameLog {
    /// A log if `TSM_FRAME_LOG` is set.
    pub fn from_env() -> Option<FrameLog> {
        std::env::var_os("TSM_FRAME_LOG").map(|_| FrameLog::fresh(None))
    }

    fn fresh(last: Option<Instant>) -> FrameLog {
        FrameLog {
            last,
            window: Instant::now(),
            frames: 0,
            busy_frames: 0,
            intervals: 0,
            interval_sum: Duration::ZERO,
            interval_max: Duration::ZERO,
            build_sum: Duration::ZERO,
            build_max: Duration::ZERO,
        }
    }

    /// Record one frame that took `build` to lay out, with `increments` in the history.
    pub fn frame(&mut self, build: Duration, busy: bool, increments: usize) {
        let now = Instant::now();
        if let Some(last) = self.last {
            let dt = now - last;
            self.intervals += 1;
            self.interval_sum += dt;
            self.interval_max = self.interval_max.max(dt);
        }
        self.last = Some(now);
        self.frames += 1;
        self.busy_frames += u32::from(busy);
        self.build_sum += build;
        self.build_max = self.build_max.max(build);
        if now - self.window >= Duration::from_secs(2) {
            let n = self.frames.max(1);
            eprintln!(
                "frames {:>4} ({} while solving, {increments} increments): interval mean {:.2} ms max {:.2} ms; ui build mean {:.2} ms max {:.2} ms",
                self.frames,
                self.busy_frames,
                self.interval_sum.as_secs_f64() * 1e3 / f64::from(self.intervals.max(1)),
                self.interval_max.as_secs_f64() * 1e3,
                self.build_sum.as_secs_f64() * 1e3 / f64::from(n),
                self.build_max.as_secs_f64() * 1e3,
            );
            *self = FrameLog::fresh(self.last);
        }
    }
}
