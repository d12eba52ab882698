//! The fairfit JSON reader (`io::read_geometry`: curves and surfaces, element counts checked first).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    fairfit_fuzz::check(data, "g.json", |p| fairfit::io::read_geometry(p));
});
