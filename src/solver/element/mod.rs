//! The elements: the TSM beam (`beam.rs`: forces in the chord frame from total coordinates,
//! `U = J S`, tangent `K_O + K_G`; `beam_lanes.rs`: four beams at once in AVX2 lanes), the
//! 3-node contact element (`contact_element.rs`, derived with the dual numbers of `dual.rs`),
//! the element as the assembly adds it, its frictionless force turned normal to the beam's
//! surface (`contact_law.rs`), contacts at a distance from the axes and their friction where
//! the faces touch (`rim/`), Coulomb friction at its contacts (`friction.rs`), chord angles
//! (`angle.rs`), the deformed shape between the nodes (`shape.rs`) and the contact of a node
//! with a rigid obstacle (`obstacle.rs`).

pub mod angle;
pub mod beam;
#[cfg(target_arch = "x86_64")]
pub mod beam_lanes;
pub mod contact_element;
pub mod contact_law;
pub mod dual;
pub mod friction;
pub mod obstacle;
pub mod rim;
pub mod shape;
