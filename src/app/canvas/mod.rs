//! The viewport and what it draws: the deformed beams as strips (`strips.rs`, `shapes.rs`),
//! through the wgpu paint callback with its WGSL in `shaders/beams.wgsl` (`beams_gpu.rs`) or
//! the egui painter, the overlays (supports, contact nodes, handles, labels: `overlays.rs`),
//! the force diagrams (`diagrams.rs`), what the pointer is on and what it carries
//! (`query.rs`), the figure for papers drawn without the window (`figure.rs`: the PNG at any
//! size) and its SVG (`svg.rs`), and the interaction (pan, zoom, fit, dragging a
//! prescribed dof: `viewport.rs`).

pub mod beams_gpu;
pub mod diagrams;
pub mod figure;
pub mod overlays;
pub mod query;
pub mod shapes;
pub mod strips;
pub mod svg;
pub mod viewport;
