//! Measurement helpers shared by the examples (`#[path = "probe/mod.rs"] mod probe;`).

/// CPU seconds of this process, all threads: utime + stime of `/proc/self/stat` (the fields after
/// the command: state is 0, utime 11, stime 12), 100 ticks per second; 0 where it cannot be read.
pub fn process_cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after = stat.rsplit(')').next().unwrap_or("");
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}
