//! The viewport and what it draws: the deformed beams as strips (`strips.rs`, from the geometry of
//! `crate::figure::geometry`), through the wgpu paint callback with its WGSL in
//! `shaders/beams.wgsl` (`beams_gpu.rs`) or the egui painter, the overlays (supports, contact
//! nodes, handles, labels: `overlays.rs`; the moment legend and the scale bar: `legend.rs`), the
//! force diagrams and the moment colour map (`diagrams.rs`), what the pointer is on and what it
//! carries (`query.rs`), and the interaction (pan, zoom, fit, dragging a prescribed dof:
//! `viewport.rs`). The figure for papers, drawn without the window, is `crate::figure`.

pub mod beams_gpu;
pub mod diagrams;
pub mod legend;
pub mod overlays;
pub mod query;
pub mod strips;
pub mod viewport;
