//! Statistics of the evaluations (Reynolds ranges, clamps), gathered per task and published
//! once per call.

use super::*;

#[derive(Debug)]
pub(super) struct Stats {
    pub(super) panel_re: AtomicU64Pair,
    pub(super) line_re: AtomicU64Pair,
    pub(super) clamped: AtomicBool,
    pub(super) crisis: AtomicBool,
    pub(super) capped: AtomicBool,
}

/// Min/max of positive floats in atomics (positive f64 bit patterns order like the values).
#[derive(Debug)]
pub(super) struct AtomicU64Pair {
    pub(super) min: AtomicU64,
    pub(super) max: AtomicU64,
}

impl AtomicU64Pair {
    pub(super) fn new() -> Self {
        Self {
            min: AtomicU64::new(f64::INFINITY.to_bits()),
            max: AtomicU64::new(0),
        }
    }
    pub(super) fn see(&self, lo: f64, hi: f64) {
        if lo > 0.0 && lo.to_bits() < self.min.load(Ordering::Relaxed) {
            self.min.fetch_min(lo.to_bits(), Ordering::Relaxed);
        }
        if hi > 0.0 && hi.is_finite() && hi.to_bits() > self.max.load(Ordering::Relaxed) {
            self.max.fetch_max(hi.to_bits(), Ordering::Relaxed);
        }
    }
    pub(super) fn get(&self) -> Option<[f64; 2]> {
        let (lo, hi) = (
            f64::from_bits(self.min.load(Ordering::Relaxed)),
            f64::from_bits(self.max.load(Ordering::Relaxed)),
        );
        (hi > 0.0).then_some([lo, hi])
    }
}

/// Per-task statistics, merged and then published to the atomics once per call.
#[derive(Debug, Clone, Copy)]
pub(super) struct Local {
    pub(super) panel: [f64; 2],
    pub(super) line: [f64; 2],
    pub(super) clamped: bool,
    pub(super) crisis: bool,
    pub(super) capped: bool,
}

impl Local {
    pub(super) fn new() -> Self {
        Self {
            panel: [f64::INFINITY, 0.0],
            line: [f64::INFINITY, 0.0],
            clamped: false,
            crisis: false,
            capped: false,
        }
    }
    pub(super) fn merge(mut self, o: Local) -> Local {
        self.panel = [self.panel[0].min(o.panel[0]), self.panel[1].max(o.panel[1])];
        self.line = [self.line[0].min(o.line[0]), self.line[1].max(o.line[1])];
        self.clamped |= o.clamped;
        self.crisis |= o.crisis;
        self.capped |= o.capped;
        self
    }
}

impl Stats {
    pub(super) fn new() -> Self {
        Self {
            panel_re: AtomicU64Pair::new(),
            line_re: AtomicU64Pair::new(),
            clamped: AtomicBool::new(false),
            crisis: AtomicBool::new(false),
            capped: AtomicBool::new(false),
        }
    }
    pub(super) fn publish(&self, l: &Local) {
        self.panel_re.see(l.panel[0], l.panel[1]);
        self.line_re.see(l.line[0], l.line[1]);
        for (flag, v) in [
            (&self.clamped, l.clamped),
            (&self.crisis, l.crisis),
            (&self.capped, l.capped),
        ] {
            if v && !flag.load(Ordering::Relaxed) {
                flag.store(true, Ordering::Relaxed);
            }
        }
    }
}
