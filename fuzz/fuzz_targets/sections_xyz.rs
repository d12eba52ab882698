//! The section reader (`sections::read_section_file`) and the point-cloud path of `mesh_read::read_mesh`
//! (an `.xyz` file), both streamed.
#![no_main]
use fairfit::io::{mesh_read, sections};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    fairfit_fuzz::check(data, "c.xyz", |p| sections::read_section_file(p));
    fairfit_fuzz::check(data, "c.xyz", |p| mesh_read::read_mesh(p));
});
