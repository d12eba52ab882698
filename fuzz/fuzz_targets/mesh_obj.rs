//! The mesh reader (`mesh_read::read_mesh`) on a `.obj` file.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    fairfit_fuzz::check(data, "m.obj", |p| fairfit::io::mesh_read::read_mesh(p));
});
