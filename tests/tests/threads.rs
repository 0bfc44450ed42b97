//! The number of threads does not change a result (docs/theory/fem.md#threads): every parallel
//! loop computes its points and elements alone and the sums are formed in a fixed order.

mod common;
use common::*;

/// The moored cage's first second in waves (100 wave components at about 1 100 nodes, above
/// the sea's parallel threshold; more than 512 cable and load elements, above the element
/// kernels') on a pool of one thread and on one of two: the same `summary.csv` byte for byte.
#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let dir = scratch("threads");
    let text = example("moored-cage.toml")
        .replace("t_end = 60.0", "t_end = 1.0")
        .replace("output_interval = 1.0", "output_interval = 0.2");
    assert!(text.contains("t_end = 1.0") && text.contains("components = 100"));
    let scene = dir.join("moored.toml");
    std::fs::write(&scene, text).unwrap();
    let run = |threads: usize| {
        let out = dir.join(format!("out-{threads}"));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| run_file(&scene, &out));
        let json = run_json(&out);
        assert_eq!(json["status"], "completed", "{threads} threads: {json}");
        std::fs::read_to_string(out.join("summary.csv")).unwrap()
    };
    let (one, two) = (run(1), run(2));
    assert!(one.lines().count() >= 6, "{one}");
    assert_eq!(one, two);
}
