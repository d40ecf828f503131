//! The application layer of halfspace (docs/architecture.md, "The application layer"): the typed
//! cases of every run, read from TOML, JSON or a Python dict by serde with one spelling of every
//! key, or from the `kind:key=value` specifications by the one parser ([`spec`]); validated once;
//! and for each outcome one summary (the JSON keys, [`records`]) and one record (the arrays).
//! The command line (the root package) and the Python extension (python/) are parse → run →
//! write over this crate; neither builds a summary or parses a spec itself.
//!
//! - [`spec`]: the `kind:key=value` parser (profiles, materials, indenters, bodies, inhomogeneities,
//!   wear media);
//! - [`axisym`], [`contact3d`], [`fretting_wear`]: the cases of axisymmetric contact, one 3D
//!   contact and MDR fretting wear (serde; flags, files and Python dicts read the same keys);
//! - [`config`]: the fretting-loop, fretting-map and 3D-wear configurations (serde) and the
//!   readers shared by every case;
//! - [`records`]: summaries and records of axisymmetric contact, 3D contact, fretting wear and the
//!   fretting loop;
//! - [`fretting_map`]: the fretting map's parallel, checkpointed driver and its table and record;
//! - [`loop_fatigue`]: the fatigue criteria over a fretting loop's closed cycle (docs/fatigue.md);
//! - [`wear3d_mdr`]: the MDR cross-check of 3D fretting wear (docs/wear3d.md#the-mdr-cross-check);
//! - [`studies`]: the series and summaries of `halfspace study` (convergence against closed
//!   forms, the FE comparison, the fretting limit, graded wear, timings).
pub use halfspace_data as data;
pub use halfspace_fatigue as fatigue;
pub use halfspace_fretting as fretting;
pub use halfspace_mdr as mdr;
pub use halfspace_numerics as numerics;
pub use halfspace_sam as sam;

pub mod axisym;
pub mod config;
pub mod contact3d;
pub mod fretting_map;
pub mod fretting_wear;
pub mod loop_fatigue;
pub mod records;
pub mod run_files;
pub mod spec;
pub mod studies;
pub mod wear3d_mdr;
