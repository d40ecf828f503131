//! halfspace: contact mechanics of elastic half-spaces.
//!
//! Facade over the workspace crates; see `docs/architecture.md`.
pub use halfspace_data as data;
pub use halfspace_fatigue as fatigue;
pub use halfspace_fretting as fretting;
pub use halfspace_mdr as mdr;
pub use halfspace_numerics as numerics;
pub use halfspace_sam as sam;

pub mod config;
pub mod fretting_map;
pub mod loop_fatigue;
pub mod records;
pub mod run_dir;
pub mod spec;
pub mod wear3d_mdr;
