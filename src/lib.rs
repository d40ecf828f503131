//! halfspace: contact mechanics of elastic half-spaces.
//!
//! Facade over the workspace crates; see `docs/architecture.md`. The application layer (cases,
//! specs, summaries, records) is `halfspace-cases`, the figures are `halfspace-figures`; `run_dir`
//! (claiming a run's output directory) belongs to the command line.
pub use halfspace_data as data;
pub use halfspace_fatigue as fatigue;
pub use halfspace_fretting as fretting;
pub use halfspace_mdr as mdr;
pub use halfspace_numerics as numerics;
pub use halfspace_sam as sam;

pub use halfspace_cases as cases;
pub use halfspace_cases::{
    axisym, config, contact3d, fretting_map, fretting_wear, loop_fatigue, records, spec, wear3d_mdr,
};
pub use halfspace_figures as figures;
pub use halfspace_figures::animation;

pub mod run_dir;
