//! The work-precision report cannot silently go wrong: on small meshes its errors against the
//! references fall as O(h^2), and its CSV holds every measured point.

use tsm_contact::solver::Formulation;
use tsm_contact::work_precision::{csv, end_moment, mattiasson};

#[test]
fn report_errors_fall_as_h_squared_on_small_meshes() {
    for f in [Formulation::BernoulliEuler, Formulation::Timoshenko] {
        let errs = |g: &dyn Fn(usize) -> f64| [8, 16, 32].map(g);
        for k in 0..3 {
            let e = errs(&|n| mattiasson(k, n, f, 1e-8, 1).expect("converges").error);
            for w in e.windows(2) {
                let ratio = w[0] / w[1];
                assert!(
                    (3.5..4.6).contains(&ratio),
                    "{f:?} Mattiasson #{k}: errors {e:?}"
                );
            }
        }
        let e = errs(&|n| end_moment(n, f, 1e-8, 1).expect("converges").error);
        for w in e.windows(2) {
            let ratio = w[0] / w[1];
            assert!(
                (3.8..4.2).contains(&ratio),
                "{f:?} end moment: errors {e:?}"
            );
        }
    }
}

#[test]
fn csv_holds_every_point() {
    let p = vec![mattiasson(0, 4, Formulation::BernoulliEuler, 1e-8, 1).unwrap()];
    let text = csv(&p);
    assert_eq!(text.lines().count(), 2);
    let fields: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(fields[0], "Mattiasson k=1");
    assert_eq!(fields[2], "4");
    let err: f64 = fields[6].parse().unwrap();
    assert!((err - p[0].error).abs() <= 1e-15 * err.abs());
}
