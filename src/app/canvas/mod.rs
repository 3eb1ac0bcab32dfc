//! The viewport and what it draws: the deformed beams as strips (`strips.rs`, `shapes.rs`),
//! through the wgpu paint callback with its WGSL in `shaders/beams.wgsl` (`beams_gpu.rs`) or
//! the egui painter, the overlays (supports, contact nodes, handles, labels: `overlays.rs`), and
//! the interaction (pan, zoom, fit, dragging a prescribed dof: `viewport.rs`).

pub mod beams_gpu;
pub mod overlays;
pub mod shapes;
pub mod strips;
pub mod viewport;
