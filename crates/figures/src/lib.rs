//! halfspace-figures: what every figure of halfspace shows, drawn from the outcomes of the
//! application layer (docs/architecture.md, "The layers"): the series, axes, labels and colour
//! ranges of each run's figures and animations, and the drawing primitives ([`draw`]: plotters,
//! SVG / PNG / GIF, an embedded font). The command line calls one function per run; the Python
//! extension does not depend on this crate (plotters and the image crate stay out of the wheel).
//!
//! A new figure is a function in the module of its run: it takes the run's outcome and writes
//! its files atomically (a killed run leaves the old figure or the new one).

pub mod animation;
pub mod axisym;
pub mod contact3d;
pub mod draw;
pub mod fretting_loop;
pub mod fretting_map;
pub mod fretting_wear;
pub mod studies;
pub mod wear3d;

/// Why a figure was not written.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// A figure path whose extension is not one of the formats asked for (the message names the
    /// option, the path and the formats).
    #[error("{0}")]
    Extension(String),
    /// Drawing or writing a figure failed (the message names the file where the run's front end
    /// did).
    #[error("{0}")]
    Draw(String),
}
