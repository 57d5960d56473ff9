//! Object symmetries: the rules live in `cellc_schema::symmetry`, where the compiler uses
//! them too (to keep one member of a grasp family per symmetric set).

pub use cellc_schema::symmetry::*;
