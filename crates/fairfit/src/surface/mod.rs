//! Surfaces from sections and point clouds: compatible fair section curves, skinning, surface measures.
