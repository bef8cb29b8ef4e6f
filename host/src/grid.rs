//! The index buffer of a closed grid, shared by the torus and the twisting torus.

/// The triangles of a closed `nu × nv` grid (vertex `(i, j)` at index `i·nv + j`, both
/// directions wrapping), two per quad, counter-clockwise when `u` runs along `i` and `v` along
/// `j` with `∂u × ∂v` outward: the index buffer of
/// `scenes::torus` and of the twisting torus.
pub(crate) fn grid_triangles(nu: usize, nv: usize) -> Vec<[u32; 3]> {
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    let mut out = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            out.push([a, b, c]);
            out.push([a, c, d]);
        }
    }
    out
}
