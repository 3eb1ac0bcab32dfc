//! The app's UI-thread time per frame (layout and tessellation, as `egui_kittest` steps it) on a
//! cantilever of 20,000 elements with its run finished, the pointer resting on the beam: what a
//! user pays for every repaint while reading a large model's results.

use criterion::{criterion_group, criterion_main, Criterion};
use egui_kittest::Harness;
use tsm_contact::app::{Startup, TsmApp};

/// A 10 m cantilever of `n` elements with a tip load that bends it by a tenth of its length.
fn cantilever(n: usize) -> String {
    format!(
        r#"(
    name: "long cantilever",
    sections: [(name: "s", E: 2.0e11, A: 1.0e-3, I: 1.0e-7)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (10.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: {}, fy: -60.0)],
    control: (steps: 1),
)"#,
        n + 1
    )
}

fn frame(c: &mut Criterion) {
    let path = std::env::temp_dir().join(format!("tsm-frame-{}.ron", std::process::id()));
    std::fs::write(&path, cantilever(20_000)).unwrap();
    let startup = Startup {
        steps: Some(1),
        ..Startup::scene(&path.to_string_lossy())
    };
    let mut h = Harness::builder()
        .with_size([1400.0, 900.0])
        .build_eframe(move |cc| TsmApp::new(cc, startup));
    // Until the step is solved and shown.
    let t0 = std::time::Instant::now();
    while h.state().increments() < 1 {
        h.step();
        assert!(t0.elapsed().as_secs() < 120, "the step did not finish");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    h.step();
    let (_, at) = h.state().node_on_screen(10_001).expect("mid-span is drawn");
    h.hover_at(at);
    h.step();
    c.bench_function("frame_20000_elements_hovered", |b| b.iter(|| h.step()));
    std::fs::remove_file(path).ok();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = frame
}
criterion_main!(benches);
