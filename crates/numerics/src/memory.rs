//! Memory checked before allocating: solvers estimate their footprint from the problem size and
//! refuse, with the estimate, a request that would not fit (instead of aborting in the allocator
//! or being killed by the kernel).

use crate::NumericsError;

/// Bytes available to a new allocation: `MemAvailable` of `/proc/meminfo`, lowered by the
/// environment variable `HALFSPACE_MEMORY_LIMIT` (bytes) when set; `None` when neither is known
/// (then nothing is refused).
pub fn available_bytes() -> Option<f64> {
    let limit = std::env::var("HALFSPACE_MEMORY_LIMIT")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v > 0.0);
    let meminfo = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
                .map(|kb| kb * 1024.0)
        });
    match (limit, meminfo) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Refuses `bytes` (an estimate, as `f64` so that huge requests cannot overflow) when it exceeds
/// [`available_bytes`].
pub fn check_fits(what: &'static str, bytes: f64) -> Result<(), NumericsError> {
    match available_bytes() {
        Some(available) if bytes.is_nan() || bytes > available => Err(NumericsError::OutOfMemory {
            what,
            needed_gib: bytes / GIB,
            available_gib: available / GIB,
        }),
        _ => Ok(()),
    }
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Bytes of the padded 2D FFT plan [`crate::fft2d::Fft2d`] on `N₁ × N₂` cells (padded real field
/// and row spectra) plus `spectra` complex spectra of `2N₁(N₂ + 1)` values.
pub fn fft2d_bytes(n1: usize, n2: usize, spectra: f64) -> f64 {
    let (n1, n2) = (n1 as f64, n2 as f64);
    let real = 4.0 * n1 * n2 * 8.0;
    let spectrum = 2.0 * n1 * (n2 + 1.0) * 16.0;
    real + spectrum * (1.0 + spectra)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_requests_are_refused_with_the_estimate() {
        // 1e5 × 1e5 cells: ~1.4 TB for one padded plan, beyond any machine this runs on.
        let bytes = fft2d_bytes(100_000, 100_000, 1.0);
        let err = check_fits("a test grid", bytes).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("a test grid needs about"), "{text}");
        assert!(check_fits("a small grid", 1e3).is_ok());
        assert!(check_fits("NaN bytes", f64::NAN).is_err() || available_bytes().is_none());
    }
}
