//! STEP and IGES files as input (`src/commands/cad_input.rs`): fairfit's own files, composite curves,
//! conics written by OpenCASCADE, and sections for `fairfit surface`.

mod composite;
mod conics;
mod files;
mod sections;
