//! Contact: the acceptance rule, the independent oracle, beams, obstacles, friction, self-contact, drags and load paths.
//! One test binary; each module is one subject (`cargo test --release --test contact -- MODULE::`).

#[path = "../common/mod.rs"]
mod common;

mod acceptance;
mod arcs;
mod bar_on_a_beam_floor;
#[cfg(feature = "reports")]
mod campaign;
mod channel;
mod contact;
mod drags;
mod friction;
mod load_paths;
mod long_slides;
mod mesh_node_contact;
mod obstacle_campaign;
mod obstacle_sets;
mod obstacles;
mod oracle;
mod punch;
mod rims;
mod rolling;
mod self_contact;
mod snap;
mod thickness;
mod tip_on_node;
