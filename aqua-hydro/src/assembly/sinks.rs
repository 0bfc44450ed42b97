//! Where an element's results go: compact Jacobian blocks (bulk) or a dense element matrix.

use super::*;

/// Where an element's results go.
pub(super) trait Sink {
    fn force(&mut self, local: usize, f: V3);
    fn mass(&mut self, local: usize, m: &M3);
    fn dv(&mut self, piece: usize, nodes: &[usize], d: &M3);
    fn dx(&mut self, piece: usize, nodes: &[usize], q: usize, d: &M3);
}

pub(super) fn to_block(m: &M3) -> Block {
    [
        [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
        [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
        [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
    ]
}

/// Sink of the bulk path: element forces and one mass block, plus its compact blocks.
pub(super) struct CompactSink<'a> {
    pub(super) force: &'a mut [[f64; 3]; MAX_NODES],
    pub(super) mass: &'a mut Block,
    pub(super) dv: &'a mut [Block],
    pub(super) dx: &'a mut [Block],
    pub(super) piece_len: usize,
}

impl Sink for CompactSink<'_> {
    #[inline]
    fn force(&mut self, local: usize, f: V3) {
        let t = &mut self.force[local];
        t[0] += f.x;
        t[1] += f.y;
        t[2] += f.z;
    }
    #[inline]
    fn mass(&mut self, _local: usize, m: &M3) {
        // all nodes of a line/point receive the same share: keep one block
        *self.mass = to_block(m);
    }
    #[inline]
    fn dv(&mut self, piece: usize, _nodes: &[usize], d: &M3) {
        self.dv[piece] = to_block(d);
    }
    #[inline]
    fn dx(&mut self, piece: usize, _nodes: &[usize], q: usize, d: &M3) {
        self.dx[piece * self.piece_len + q] = to_block(d);
    }
}

/// Sink of the element path: dense matrices.
pub(super) struct DenseSink<'a>(pub(super) &'a mut ElementOutput);

impl Sink for DenseSink<'_> {
    fn force(&mut self, local: usize, f: V3) {
        for k in 0..3 {
            self.0.force[local][k] += f[k];
        }
    }
    fn mass(&mut self, local: usize, m: &M3) {
        for r in 0..3 {
            for c in 0..3 {
                self.0.added_mass[local][r][c] += m[(r, c)];
            }
        }
    }
    fn dv(&mut self, _piece: usize, nodes: &[usize], d: &M3) {
        for &i in nodes {
            for &j in nodes {
                for r in 0..3 {
                    for c in 0..3 {
                        self.0.dfdv[3 * i + r][3 * j + c] += d[(r, c)];
                    }
                }
            }
        }
    }
    fn dx(&mut self, _piece: usize, nodes: &[usize], q: usize, d: &M3) {
        let j = nodes[q];
        for &i in nodes {
            for r in 0..3 {
                for c in 0..3 {
                    self.0.dfdx[3 * i + r][3 * j + c] += d[(r, c)];
                }
            }
        }
    }
}
