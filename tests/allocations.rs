//! The engine does not allocate per step: an outcome run allocates nothing, and
//! a full history allocates the same however many steps it takes.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use topple::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulseShape, Record, Solver, simulate,
};

struct Counting;

thread_local! {
    /// Allocations made by this thread: the test harness's other threads
    /// (its output, its timers) allocate too, and must not be counted.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // `try_with`: no count while the thread's locals are being torn down.
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn count<F: FnOnce()>(f: F) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn simulations_do_not_allocate_per_step() {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    let sine = Pulse::new(PulseShape::OneSine, 4.0 * 0.25 * 9.81, 5.0 * 2.14).expect("valid");
    let ricker = |symmetric| {
        Pulse::new(
            PulseShape::Ricker { symmetric },
            4.0 * 0.25 * 9.81,
            5.0 * 2.14,
        )
        .expect("valid")
    };
    let mavroeidis_papageorgiou = |gamma, nu| {
        Pulse::new(
            PulseShape::mavroeidis_papageorgiou(gamma, nu).expect("valid"),
            4.0 * 0.25 * 9.81,
            2.0 * 2.14,
        )
        .expect("valid")
    };
    let pulse = sine;
    for (pulse, formulation) in [
        (sine, Formulation::Linear),
        (sine, Formulation::Nonlinear),
        (ricker(true), Formulation::Nonlinear),
        (ricker(false), Formulation::Nonlinear),
        (mavroeidis_papageorgiou(2.0, 0.0), Formulation::Nonlinear),
        (mavroeidis_papageorgiou(7.5, 1.0), Formulation::Linear),
    ] {
        let problem = Problem {
            block,
            pulse,
            formulation,
        };
        for method in [Method::Dopri5, Method::Dop853] {
            let solver = |rtol: f64| Solver::RungeKutta {
                method,
                rtol,
                atol: rtol / 100.0,
            };
            let outcome = count(|| {
                simulate(&problem, &Options::outcome(solver(1e-10))).expect("simulates");
            });
            assert_eq!(outcome, 0, "{method:?} outcome run allocated");
            let coarse = count(|| {
                simulate(&problem, &Options::history(solver(1e-5))).expect("simulates");
            });
            let fine = count(|| {
                simulate(&problem, &Options::history(solver(1e-12))).expect("simulates");
            });
            assert_eq!(
                coarse, fine,
                "{method:?}: allocations grow with the step count"
            );
        }
    }
    let problem = Problem {
        block,
        pulse,
        formulation: Formulation::Linear,
    };
    assert_eq!(
        count(|| {
            simulate(&problem, &Options::outcome(Solver::Exact)).expect("simulates");
        }),
        0
    );
    // The same pulse as a record: the exact solution runs piece by piece,
    // allocating nothing per piece, however many pieces.
    let sampled = |n: usize| {
        let dt = sine.duration / n as f64;
        let acc: Vec<f64> = (0..=n)
            .map(|k| sine.amplitude * (sine.circular_frequency * k as f64 * dt).sin())
            .collect();
        Problem {
            block,
            pulse: Record::new(acc.into(), dt).expect("valid record"),
            formulation: Formulation::Linear,
        }
    };
    let (coarse, fine) = (sampled(500), sampled(5000));
    for problem in [&coarse, &fine] {
        let outcome = count(|| {
            simulate(problem, &Options::outcome(Solver::Exact)).expect("simulates");
        });
        assert_eq!(outcome, 0, "exact outcome run on a record allocated");
    }
    let full = |problem: &Problem<Record>| {
        count(|| {
            simulate(problem, &Options::history(Solver::Exact)).expect("simulates");
        })
    };
    assert_eq!(
        full(&coarse),
        full(&fine),
        "exact on a record: allocations grow with the pieces"
    );
}
