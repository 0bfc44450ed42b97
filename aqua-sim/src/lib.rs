//! aqua-sim: the simulator as a library.
//!
//! A scene (TOML, [`scene`]) becomes a model (`build`): the merged mesh (aqua-mesh), the
//! structural model (aqua-fem), the sea (aqua-env) and the water-load elements (aqua-hydro).
//! [`plan`] validates the analysis (the one validation `aqua check` and `aqua run` share),
//! [`run`] drives statics and dynamics through the solvers (`solvers`, the only caller of
//! aqua-fem's `solve_static`, `DynamicSolver` and `ExplicitSolver`), `post` computes the
//! physical outputs of each output step, [`extremes`] the load extremes over every step,
//! `files` writes them, [`run_scene`] is a whole run with every output file (the one `aqua
//! run`, Python and the tests share), and [`coupling`] lets another code drive prescribed
//! nodes step by step.
//!
//! Governing equations (docs/theory/fem.md#model-and-unknowns, #static-solver to
//! #explicit-schemes): the semi-discrete equations of motion of the cable network
//!
//! ```text
//! M ẍ + C ẋ + f_int(x) = f_g + f_w(x, ẋ, ẍ, t) + f_c(x)      (free DOFs)
//! x_i(t) = X_i + d_i(t)                                       (prescribed nodes)
//! ```
//!
//! with f_w the water loads of [`provider::WaterLoads`] (screen panels, Morison lines, point
//! bodies, wake shielding) and f_c the seabed contact; statics solves f_int = f_g + f_w + f_c
//! with ẋ = ẍ = 0 and the full current.
//!
//! Errors are typed ([`SimError`]): the `aqua` binary and the Python module turn them into
//! text; warnings are [`Diagnostic`]s.

pub mod body;
mod build;
pub mod buoy;
pub mod check;
mod check_text;
pub mod coupling;
mod csv;
pub mod design;
pub mod diagnostic;
pub mod error;
pub mod estimate;
pub mod extremes;
mod files;
mod mesh_sequence;
pub mod net_triangles;
pub mod overrides;
pub mod pipe_stress;
pub mod plan;
mod post;
pub mod provider;
pub mod run;
mod run_json;
mod run_scene;
mod run_text;
pub mod scene;
mod solvers;

pub use build::{Built, Prescribed, build_mesh, resolve_ref};
pub use coupling::Coupling;
pub use csv::{csv_field, csv_line};
pub use diagnostic::{Diagnostic, Severity};
pub use error::{ModelError, Result, SimError};
pub use extremes::{Extreme, Extremes};
pub use files::{RunFiles, write_component_table, write_kinematics};
pub use overrides::Override;
pub use plan::{Integrator, Plan, PrepareOptions, Prepared, SceneSource, prepare};
pub use post::{SummaryRow, net_force, total_volume};
pub use run::{Ending, Frame, Observer, RunRecord, Simulation};
pub use run_scene::{RunOptions, RunOutcome, Written, run_scene};
pub use scene::{Scene, SceneInput, read_scene};
pub use solvers::{Stepper, start_integrator, static_equilibrium};
