//! Failures keep their type end to end: a load provider's own error reaches the caller as that
//! type, and a failed step says why as a [`FailureReason`] whose hint names only what its scheme
//! has (docs/theory/fem.md#step-control).

use aqua_fem::*;

/// A provider's own error type, with data a caller may act on.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("the sea is undefined at depth {depth} m")]
struct SeaUndefined {
    depth: f64,
}

/// A provider that fails on every element with [`SeaUndefined`].
struct FailingSea {
    nodes: Vec<[usize; 2]>,
}

impl LoadProvider for FailingSea {
    fn n_elements(&self) -> usize {
        self.nodes.len()
    }
    fn element_nodes(&self, e: usize) -> &[usize] {
        &self.nodes[e]
    }
    fn element_load(
        &self,
        _e: usize,
        _t: f64,
        x: &[[f64; 3]],
        _v: &[[f64; 3]],
        _want: Want,
        _out: &mut ElementLoad,
    ) -> std::result::Result<(), LoadError> {
        Err(LoadError::new(SeaUndefined { depth: x[0][2] }))
    }
}

/// A hanging rope of `n` segments from a fixed top at z = 0, stretched by 1 % as built.
fn rope(n: usize, ea: f64) -> (Model, Vec<usize>) {
    let mut b = ModelBuilder::new(Environment::default());
    let g = b.add_group("rope", CableSection::new(ea, 1.0)).unwrap();
    let nodes: Vec<usize> = (0..=n)
        .map(|i| b.add_node([0.0, 0.0, -(i as f64)]).unwrap())
        .collect();
    for w in nodes.windows(2) {
        b.add_cable(w[0], w[1], g, UnstretchedLength::Given(0.99))
            .unwrap();
    }
    b.fix(nodes[0], Dofs::ALL).unwrap();
    (b.build().unwrap(), nodes)
}

#[test]
fn a_providers_error_reaches_the_caller_with_its_type() {
    let (model, _) = rope(4, 1e6);
    let mut sea = FailingSea {
        nodes: model.elements().iter().map(|e| [e.a, e.b]).collect(),
    };
    let err = solve_static(&model, &mut sea, &StaticSettings::default()).unwrap_err();
    let FemError::Load { error, .. } = &err else {
        panic!("expected the provider's error, got {err}");
    };
    // The caller gets the provider's type back, with its data, not a message.
    let sea_err = error
        .inner()
        .downcast_ref::<SeaUndefined>()
        .unwrap_or_else(|| panic!("the provider's type was lost: {err}"));
    assert!(sea_err.depth <= 0.0, "{sea_err:?}");
    assert!(err.to_string().contains("the sea is undefined"), "{err}");
}

/// A rope whose strain guard is below the strain its own weight gives: every step fails on it
/// whatever the step, and the failure says so as a typed reason with a fitting hint.
#[test]
fn a_failed_step_says_why_as_a_typed_reason_with_its_schemes_hint() {
    for midpoint in [false, true] {
        let (model, _) = rope(4, 1e3);
        let mut s = DynamicSettings::new(0.01, 0.1);
        s.midpoint = midpoint;
        // Weight of 4 m of rope at 1 kg/m on EA = 1 kN: strain ≈ 0.04 at the top.
        s.max_strain = 0.02;
        s.dt_min = Some(0.01 / 8.0);
        let mut solver = DynamicSolver::new(&model, s, None, &mut NoLoads).unwrap();
        let err = loop {
            match solver.step(&mut NoLoads) {
                Ok(_) if solver.is_finished() => panic!("midpoint {midpoint}: no failure"),
                Ok(_) => continue,
                Err(e) => break e,
            }
        };
        let FemError::StepFailed(f) = &err else {
            panic!("midpoint {midpoint}: expected a step failure, got {err}");
        };
        let FailureReason::StrainLimit { strain, max_strain } = f.reason else {
            panic!(
                "midpoint {midpoint}: expected the strain guard, got {:?}",
                f.reason
            );
        };
        assert!(
            strain > max_strain && max_strain == 0.02,
            "{strain} {max_strain}"
        );
        assert_eq!(f.reason.kind(), FailureKind::StrainLimit);
        assert_eq!(
            f.scheme,
            if midpoint {
                SchemeKind::Midpoint
            } else {
                SchemeKind::Hht
            }
        );
        // The hint points at the section and the guard, and the step control counted the
        // halvings under that kind.
        let msg = err.to_string();
        assert!(msg.contains("EA") && msg.contains("max_strain"), "{msg}");
        let control = solver.step_control();
        assert_eq!(control.reasons.len(), 1, "{:?}", control.reasons);
        assert_eq!(control.reasons[0].0, FailureKind::StrainLimit);
        assert_eq!(control.events[0].kind, FailureKind::StrainLimit);
    }
}
