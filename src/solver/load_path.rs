//! A load path: the stages a run goes through one after the other. Over each stage's steps the
//! factor of every load group and the value of every prescribed dof move linearly from where
//! the stage starts to where it ends (the stage's last step lands on its end values exactly), or
//! a prescribed dof passes through listed values, one per step (a drag kept as it was made).
//! Holding, unloading and reversing are stages like any other.

use serde::{Deserialize, Serialize};

/// How one prescribed dof, or one load group's factor, moves over a stage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum StageMotion {
    /// Linearly from its value at the stage's start to this value at its end (m or rad, or a
    /// factor).
    To(f64),
    /// Through these values, one at the end of each step of the stage.
    Values(Vec<f64>),
}

impl StageMotion {
    /// The value at the stage's end.
    pub fn end(&self) -> f64 {
        match self {
            StageMotion::To(v) => *v,
            StageMotion::Values(v) => v.last().copied().unwrap_or(0.0),
        }
    }

    /// The value at the end of step `i` (1-based) of `n`, from `start`.
    fn at(&self, start: f64, i: usize, n: usize) -> f64 {
        match self {
            StageMotion::To(v) => ramp(start, *v, i, n),
            StageMotion::Values(v) => v[i - 1],
        }
    }
}

/// `from` moved linearly toward `to`, at step `i` of `n`: exactly `to` at the last step.
fn ramp(from: f64, to: f64, i: usize, n: usize) -> f64 {
    if i >= n {
        to
    } else {
        from + (to - from) * (i as f64 / n as f64)
    }
}

/// One stage of a load path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stage {
    /// Its name, as the scene gives it (or "stage N").
    pub name: String,
    /// Number of steps, at least one.
    pub steps: usize,
    /// How the factor of each load group (`Model::load_groups`) moves over the stage.
    pub factors: Vec<StageMotion>,
    /// How each prescribed dof (`Model::prescribed`) moves over the stage.
    pub prescribed: Vec<StageMotion>,
}

/// Where one step of a path lands: the prescribed values and the load factors at its end.
#[derive(Clone, Debug, PartialEq)]
pub struct PathPoint {
    /// The stage the step belongs to (index into [`LoadPath::stages`]).
    pub stage: usize,
    /// The prescribed values at the step's end, one per `Model::prescribed`.
    pub prescribed: Vec<f64>,
    /// The load factors at the step's end, one per load group.
    pub factors: Vec<f64>,
}

/// The stages of a run, in order; the run starts from zero loads and zero prescribed values.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LoadPath {
    /// The stages.
    pub stages: Vec<Stage>,
}

impl LoadPath {
    /// The number of steps of the whole path.
    pub fn total_steps(&self) -> usize {
        self.stages.iter().map(|s| s.steps).sum()
    }

    /// The stage that step `k` (0-based over the whole path) belongs to, and the step's number
    /// within it (1-based); none past the path's end.
    pub fn locate(&self, k: usize) -> Option<(usize, usize)> {
        let mut first = 0;
        for (s, stage) in self.stages.iter().enumerate() {
            if k < first + stage.steps {
                return Some((s, k - first + 1));
            }
            first += stage.steps;
        }
        None
    }

    /// The step that ends stage `s` (0-based over the whole path).
    pub fn last_step_of(&self, s: usize) -> usize {
        self.stages[..=s].iter().map(|st| st.steps).sum::<usize>() - 1
    }

    /// The prescribed values and load factors where stage `s` starts (zero for the first).
    fn start_of(&self, s: usize, prescribed: usize, groups: usize) -> (Vec<f64>, Vec<f64>) {
        match s.checked_sub(1).map(|p| &self.stages[p]) {
            None => (vec![0.0; prescribed], vec![0.0; groups]),
            Some(prev) => (
                prev.prescribed.iter().map(StageMotion::end).collect(),
                prev.factors.iter().map(StageMotion::end).collect(),
            ),
        }
    }

    /// Where step `k` (0-based over the whole path) lands; none past the path's end.
    pub fn point(&self, k: usize) -> Option<PathPoint> {
        let (s, i) = self.locate(k)?;
        let stage = &self.stages[s];
        let n = stage.steps;
        let (p0, f0) = self.start_of(s, stage.prescribed.len(), stage.factors.len());
        Some(PathPoint {
            stage: s,
            prescribed: (stage.prescribed.iter().zip(&p0))
                .map(|(m, &a)| m.at(a, i, n))
                .collect(),
            factors: (stage.factors.iter().zip(&f0))
                .map(|(m, &a)| m.at(a, i, n))
                .collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path() -> LoadPath {
        LoadPath {
            stages: vec![
                Stage {
                    name: "press".into(),
                    steps: 4,
                    factors: vec![StageMotion::To(1.0)],
                    prescribed: vec![StageMotion::To(0.0)],
                },
                Stage {
                    name: "drag".into(),
                    steps: 3,
                    factors: vec![StageMotion::To(1.0)],
                    prescribed: vec![StageMotion::Values(vec![0.1, 0.3, 0.2])],
                },
                Stage {
                    name: "back".into(),
                    steps: 2,
                    factors: vec![StageMotion::To(0.0)],
                    prescribed: vec![StageMotion::To(-0.2)],
                },
            ],
        }
    }

    #[test]
    fn steps_are_located_in_their_stages() {
        let p = path();
        assert_eq!(p.total_steps(), 9);
        assert_eq!(p.locate(0), Some((0, 1)));
        assert_eq!(p.locate(3), Some((0, 4)));
        assert_eq!(p.locate(4), Some((1, 1)));
        assert_eq!(p.locate(8), Some((2, 2)));
        assert_eq!(p.locate(9), None);
        assert_eq!(p.last_step_of(1), 6);
    }

    #[test]
    fn a_stage_ramps_from_where_the_last_one_ended_and_lands_exactly() {
        let p = path();
        assert_eq!(p.point(1).unwrap().factors, vec![0.5]);
        assert_eq!(p.point(3).unwrap().factors, vec![1.0]);
        assert_eq!(p.point(5).unwrap().prescribed, vec![0.3]);
        // From 0.2 (the listed values' last) toward -0.2 in two steps.
        let mid = p.point(7).unwrap();
        assert!((mid.prescribed[0] - 0.0).abs() < 1e-15);
        assert_eq!(mid.factors, vec![0.5]);
        assert_eq!(p.point(8).unwrap().prescribed, vec![-0.2]);
        assert_eq!(p.point(8).unwrap().stage, 2);
    }
}
