//! Tests of the `aqua mesh` and `aqua coeffs` commands through the library API of aqua-cli.

mod mesh {
    use aqua_cli::commands::mesh::*;
    #[allow(unused_imports)]
    use std::path::{Path, PathBuf};

    fn tmp(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("aqua-cli-mesh-{}-{name}", std::process::id()))
    }

    #[test]
    fn builders_write_vtm() {
        let out = tmp("ssm.vtm");
        let args = Args {
            kind: Some(Kind::Ssm),
            circumference: Some(120.0),
            depth: Some(15.0),
            out: Some(out.clone()),
            json: true,
            ..Default::default()
        };
        run(args).unwrap();
        // The multiblock file lists the block files in the folder named after it.
        let vtm = std::fs::read_to_string(&out).unwrap();
        let blocks = tmp("ssm");
        for kind in ["lines", "panels", "points"] {
            let file = format!("cage0_{kind}.vtu");
            assert!(vtm.contains(&format!("name=\"{kind}\" file=\"")), "{vtm}");
            assert!(blocks.join(&file).is_file(), "{file} missing");
        }
        std::fs::remove_file(&out).unwrap();
        std::fs::remove_dir_all(&blocks).unwrap();
        let panel = Args {
            kind: Some(Kind::Panel),
            width: Some(1.0),
            height: Some(1.0),
            fixed: vec!["top".into()],
            ..Default::default()
        };
        run(panel).unwrap();
        let line = Args {
            kind: Some(Kind::Line),
            anchor: Some([-100.0, 0.0, -50.0]),
            fairlead: Some([0.0, 0.0, 0.0]),
            length: Some(130.0),
            segments: Some(20),
            diameter: Some(0.1),
            ea: Some(1e8),
            mass_per_length: Some(50.0),
            ..Default::default()
        };
        run(line).unwrap();
        let fixture =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../aqua-mesh/tests/fixtures/net_v22.msh");
        run(Args {
            from: Some(fixture),
            ..Default::default()
        })
        .unwrap();
    }

    #[test]
    fn bad_input_is_input_error() {
        let cases = [
            Args {
                kind: Some(Kind::Ssm),
                element_length: Some(40.0),
                ..Default::default()
            },
            Args {
                kind: Some(Kind::Ssm),
                width: Some(3.0),
                ..Default::default()
            },
            Args {
                kind: Some(Kind::Csm),
                tube_depth: Some(3.0),
                ..Default::default()
            },
            Args {
                from: Some("/nonexistent/net.msh".into()),
                ..Default::default()
            },
            Args {
                kind: Some(Kind::Cct),
                out: Some(tmp("cage.vtk")),
                ..Default::default()
            },
            Args {
                kind: Some(Kind::Cct),
                out: Some(tmp("cage.vtu")),
                ..Default::default()
            },
            Args::default(),
        ];
        for a in cases {
            let e = run(a).unwrap_err();
            assert!(aqua_cli::is_input_error(&e), "{e:#}");
        }
    }
}

mod coeffs {
    use aqua_cli::commands::coeffs::*;
    #[allow(unused_imports)]
    use std::path::{Path, PathBuf};

    fn args(model: &str) -> Args {
        Args {
            model: model.into(),
            solidity: 0.2,
            angles: "0:90:30".into(),
            twine_diameter: 0.0024,
            speed: 0.5,
            viscosity: 1.19e-6,
            cyl_cd: None,
            cd: None,
            cl: None,
            reynolds: "1000,5e5".into(),
            json: false,
        }
    }

    #[test]
    fn s1_table_matches_spec() {
        let r = compute(&args("S1")).unwrap();
        let sc = r.screen.unwrap();
        assert!(r.morison.is_none());
        let rows = &sc.models[0].rows;
        assert_eq!(rows.len(), 4);
        // docs/theory/hydrodynamics.md#screen-coefficient-values, Sn = 0.2
        assert!((rows[1].cd - 0.2305255888).abs() < 5e-11);
        assert!((rows[1].cl - 0.0460725515).abs() < 5e-11);
        assert!((rows[3].cd - 0.04).abs() < 1e-12);
    }

    #[test]
    fn s3_chain_uses_reynolds_from_speed_and_diameter() {
        let mut a = args("S3");
        a.angles = "0,45".into();
        let sc = compute(&a).unwrap().screen.unwrap();
        assert!((sc.models[0].rows[0].cd - 0.2732876264).abs() < 5e-11);
        assert!((sc.models[0].rows[1].cl - 0.0552477762).abs() < 5e-11);
        a.cyl_cd = Some(1.2);
        let sc = compute(&a).unwrap().screen.unwrap();
        assert!((sc.models[0].rows[0].cd - 0.3375).abs() < 1e-12);
    }

    #[test]
    fn m4_table_matches_spec() {
        let r = compute(&args("M4")).unwrap();
        let m = &r.morison.unwrap().models[0];
        assert!((m.rows[0].cn - 1.2264911064).abs() < 5e-11);
        assert!((m.rows[0].ct - 0.0810296138).abs() < 5e-11);
        assert!((m.rows[1].cn - 0.2269684010).abs() < 5e-11);
    }

    #[test]
    fn all_puts_models_side_by_side() {
        let r = compute(&args("all")).unwrap();
        let sc = r.screen.as_ref().unwrap();
        assert_eq!(sc.models.len(), 7); // const only with --cd
        assert_eq!(r.morison.as_ref().unwrap().models.len(), 5);
        let text = r.to_text();
        assert!(text.contains("bi2014 Cd") && text.contains("M5 Ct"));
        let json = serde_json::to_value(&r).unwrap();
        assert_eq!(json["screen"]["models"][0]["model"], "S1");
        let mut a = args("all");
        a.cd = Some(0.3);
        assert_eq!(compute(&a).unwrap().screen.unwrap().models.len(), 8);
    }

    #[test]
    fn bad_input_is_input_error() {
        let is_input = |r: anyhow::Result<Report>| aqua_cli::is_input_error(&r.unwrap_err());
        assert!(is_input(compute(&args("S7"))));
        let mut a = args("S1");
        a.solidity = 1.0;
        let e = compute(&a).unwrap_err().to_string();
        assert!(
            e.contains("--solidity = 1") && e.contains("0 < Sn < 1"),
            "{e}"
        );
        a.solidity = 0.2;
        a.angles = "0:120:30".into();
        assert!(is_input(compute(&a)));
        a.angles = "30:0:10".into();
        assert!(is_input(compute(&a)));
        let mut a = args("const");
        assert!(is_input(compute(&a)));
        a.cd = Some(-1.0);
        let e = compute(&a).unwrap_err().to_string();
        assert!(e.contains("-1") && e.contains(">= 0"), "{e}");
        let mut a = args("M4");
        a.reynolds = "0,10".into();
        assert!(is_input(compute(&a)));
        a.reynolds = "1:1e7:8".into();
        assert_eq!(
            compute(&a).unwrap().morison.unwrap().models[0].rows.len(),
            8
        );
        let mut a = args("S4");
        a.speed = -1.0;
        assert!(is_input(compute(&a)));
    }
}
