//! The point reader (`io::read_points`: CSV, whitespace columns, Selig/Lednicer airfoil tables), streamed.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    fairfit_fuzz::check(data, "p.csv", |p| fairfit::io::points::read_points(p));
});
