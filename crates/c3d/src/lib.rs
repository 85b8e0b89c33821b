//! The C3D file format: bytes <-> model.
