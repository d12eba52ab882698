//! The STEP reader (`cad_read::read_contents` on a `.step` file: every curve and surface it holds).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    fairfit_fuzz::check(data, "c.step", |p| fairfit::io::cad_read::read_contents(p));
});
