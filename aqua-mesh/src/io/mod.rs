//! Files in and out: gmsh import ([`gmsh`]) and VTK export ([`vtm`]).

pub mod gmsh;
pub mod vtm;
