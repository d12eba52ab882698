//! The mesh reader (`mesh_read::read_mesh`) on a `.stl` file.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    fairfit_fuzz::check(data, "m.stl", |p| fairfit::io::mesh_read::read_mesh(p));
});
