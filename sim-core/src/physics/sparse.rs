//! # The sparse linear system of the implicit step: 3×3 blocks → faer sparse Cholesky
//!
//! The Newton system of backward Euler (`H Δx = −∇E`, H symmetric positive definite) has one
//! 3×3 block per pair of vertices that share an element: the diagonal, every mesh edge, and
//! the two wing vertices of every hinge (they are not mesh neighbours). The pattern is fixed
//! for a given mesh, so everything symbolic is done once when the mesh is built:
//!
//! 1. list the block pairs `(i, j)`, `i ≤ j` (diagonal blocks first, then off-diagonal pairs
//!    sorted);
//! 2. build the scalar upper-triangular CSC pattern of the 3n × 3n matrix and, for each block
//!    entry, the slot of its value in the CSC value array (`scatter`);
//! 3. run faer's symbolic Cholesky (AMD fill-reducing ordering, supernodal) and allocate the
//!    factor values and the scratch memory of the numeric factorization and the solve. The
//!    supernodal variant is forced: measured on scenario S1 it is faster than faer's automatic
//!    choice (simplicial for these sizes) from 130 triangles up — 0.34 vs 0.39 ms per frame at
//!    130 triangles, 2.6 vs 8.0 ms at 567, 6.1 vs 17.9 ms at 1 073 — because the Hessian is
//!    made of dense 3×3 blocks.
//!
//! 4. store the matrix already permuted: the scalar pattern is re-indexed by the AMD
//!    ordering and kept as the lower triangle, the side faer's supernodal factorization works
//!    on, and the symbolic factorization is redone on it with the identity ordering. Each
//!    numeric factorization then reads the values in place; with the ordering left to faer it
//!    permuted and transposed the whole matrix into scratch memory every time (6 % of a C5
//!    frame measured with `perf`). The right-hand side is permuted before the solve and the
//!    solution back after it (3n copies).
//!
//! 5. keep room for up to [`LOW_RANK_CAPACITY`] **rank-one terms u uᵀ** that couple vertices
//!    sharing no block (the sheet–sheet contact pairs of `sheet_contact.rs`, whose two layers
//!    are anywhere in the mesh). They are not put in the pattern, which would change the
//!    fill-reducing ordering, the factor and its allocation whenever a pair comes or goes.
//!    The solve takes them through the Woodbury identity instead: with A the factorized
//!    pattern matrix and U = [u_1 … u_p],
//!
//!    ```text
//!    (A + U Uᵀ)⁻¹ b = y − Z (I + Uᵀ Z)⁻¹ Uᵀ y,    y = A⁻¹ b,  Z = A⁻¹ U
//!    ```
//!
//!    With the factor split, A = L Lᵀ, the same identity needs only forward solves for U:
//!
//!    ```text
//!    W = L⁻¹ U,   C = I + Wᵀ W,   x = L⁻ᵀ (L⁻¹ b − W C⁻¹ Wᵀ L⁻¹ b)
//!    ```
//!
//!    that is, one forward pass through the factor with the p columns of U as right-hand
//!    sides (blocked), the dense p × p product Wᵀ W and Cholesky factorization of the
//!    capacitance matrix C (symmetric positive definite whatever U is), and the right-hand
//!    side's forward and backward passes with the correction between them. Solving Z = A⁻¹ U
//!    whole instead spends a backward pass per column, a quarter of the linear solver's time in
//!    the crumples; split, their p99 frames are 7–8 % shorter (docs/benchmarks.md, "Woodbury on
//!    the split factor"). Each u has at most 12 non-zeros (four vertices × 3), kept in the
//!    factor's order.
//!
//! 6. factorize each supernode's diagonal block with faer's dense Cholesky recursing down to
//!    blocks of [`SUPERNODE_RECURSION_COLS`] columns (faer's default: 64), so the root supernode
//!    of our crumpled sheets (60–66 columns) and the next largest are factorized as blocks
//!    updated by matrix products instead of column by column: 16 gave S4 the shortest mean
//!    frame of 64, 32, 16, 8 and 4 (docs/benchmarks.md, "The supernodes' dense Cholesky
//!    recursing down to 16 columns"). It changes the factor's rounding (not its accuracy), so
//!    every chaotic crumple runs a slightly different course.
//!
//! Each Newton iteration then only zeroes and fills the blocks, scatters them into the CSC
//! values (rows/columns of kinematic — handle — vertices become identity rows, so the pattern
//! never changes when hands grab or release), factorizes numerically and solves, with no
//! allocation. faer runs sequentially (`Par::Seq`): no threads inside the step (determinism).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltParams, LltRegularization};
use faer::linalg::matmul::matmul;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Accum, Conj, MatMut, Par, Side};

use std::cell::Cell;

use crate::math::M3;

thread_local! {
    /// Whether the dense kernels were run once on this thread ([`BlockSystem::warm_up`]).
    static THREAD_WARM: Cell<bool> = const { Cell::new(false) };
}

/// Runs the linear solver's dense kernels once on the current thread, so that their lazy
/// first-use allocations happen now: for a thread that will step a sheet built on another one
/// (the plugin's simulation worker). Allocates; a no-op after the first call on a thread.
pub fn warm_up_thread() {
    if !THREAD_WARM.with(Cell::get) {
        drop(BlockSystem::new(2, [[0, 1]]));
    }
}

/// Rank-one terms the solve takes through the Woodbury identity (see [`BlockSystem::add_rank_one`]).
pub const LOW_RANK_CAPACITY: usize = 64;

/// Marker for "no slot" (the lower triangle of a diagonal block).
const NO_SLOT: u32 = u32::MAX;

/// Why the linear solve failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveError {
    /// The matrix was not numerically positive definite.
    NotPositiveDefinite,
}

/// A block-sparse symmetric system with a prefactored symbolic Cholesky.
pub struct BlockSystem {
    n: usize,
    /// Off-diagonal block pairs `(i, j)`, `i < j`, sorted; block index = `n + position`.
    off_pairs: Vec<[u32; 2]>,
    /// Block values: `n` diagonal blocks, then the off-diagonal ones.
    pub blocks: Vec<M3>,
    /// The stored (lower-triangle, permuted) scalar pattern, checked once when built.
    pattern: SymbolicSparseColMat<usize>,
    values: Vec<f64>,
    scatter: Vec<[u32; 9]>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    /// Right-hand side / solution, `3n`.
    pub rhs: Vec<f64>,
    /// The right-hand side in the factor's (AMD) order, `3n`.
    permuted_rhs: Vec<f64>,
    /// `perm_fwd[k]`: the original scalar index stored at position `k` of the permuted matrix.
    perm_fwd: Vec<usize>,
    /// `perm_inv[i]`: the position in the permuted matrix of original scalar index `i`.
    perm_inv: Vec<usize>,
    /// Rank-one terms `u uᵀ` added to the matrix through the Woodbury identity, at most
    /// [`LOW_RANK_CAPACITY`]: each `u` as (permuted scalar index, value) pairs, 12 at most.
    low_rank: Vec<[(u32, f64); 12]>,
    /// Rank-one terms accepted, ≤ [`LOW_RANK_CAPACITY`].
    low_rank_limit: usize,
    /// Z = A⁻¹ U, column-major `3n × LOW_RANK_CAPACITY` (permuted order).
    lr_z: Vec<f64>,
    /// The capacitance matrix I + Uᵀ Z, column-major, `LOW_RANK_CAPACITY²`.
    lr_cap: Vec<f64>,
    /// Uᵀ y and then the capacitance system's solution, `LOW_RANK_CAPACITY`.
    lr_t: Vec<f64>,
    /// Number of numeric factorizations done (work counter for tests and benches).
    pub factorizations: u64,
    /// The factor (and the Woodbury terms' W and capacitance factor) of the last
    /// factorization is valid: [`Self::solve_again`] may use it.
    factored: bool,
    /// Rank-one terms in the last factorization's Woodbury correction.
    factored_p: usize,
}

impl std::fmt::Debug for BlockSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BlockSystem")
            .field("n", &self.n)
            .field("nnz", &self.values.len())
            .field("factor_nnz", &self.l_values.len())
            .field("factorizations", &self.factorizations)
            .finish_non_exhaustive()
    }
}

impl BlockSystem {
    /// Builds the symbolic structure for `n` vertices and the given vertex pairs (any order,
    /// duplicates and diagonal pairs allowed).
    pub fn new(n: usize, pairs: impl IntoIterator<Item = [u32; 2]>) -> Self {
        let mut off_pairs: Vec<[u32; 2]> = pairs
            .into_iter()
            .filter(|p| p[0] != p[1])
            .map(|p| [p[0].min(p[1]), p[0].max(p[1])])
            .collect();
        off_pairs.sort_unstable();
        off_pairs.dedup();
        let nb = n + off_pairs.len();

        // Scalar entries (row, col) of the upper triangle, with their (block, entry) origin.
        let mut entries: Vec<(usize, usize, u32, u8)> =
            Vec::with_capacity(6 * n + 9 * off_pairs.len());
        for i in 0..n {
            for r in 0..3 {
                for c in r..3 {
                    entries.push((3 * i + r, 3 * i + c, i as u32, (r * 3 + c) as u8));
                }
            }
        }
        for (k, p) in off_pairs.iter().enumerate() {
            let (i, j) = (p[0] as usize, p[1] as usize);
            for r in 0..3 {
                for c in 0..3 {
                    entries.push((3 * i + r, 3 * j + c, (n + k) as u32, (r * 3 + c) as u8));
                }
            }
        }
        let dim = 3 * n;
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..CholeskySymbolicParams::default()
        };
        // The fill-reducing ordering of the upper-triangle pattern (step 3)…
        let mut sorted = Vec::with_capacity(entries.len());
        sort_by_column(&mut entries, &mut sorted, dim);
        let (col_ptr, row_idx, _) = csc_pattern(dim, &entries, nb);
        let symbolic_a = SymbolicSparseColMatRef::new_checked(dim, dim, &col_ptr, None, &row_idx);
        let ordered =
            factorize_symbolic_cholesky(symbolic_a, Side::Upper, SymmetricOrdering::Amd, params)
                .expect("symbolic Cholesky of a small mesh pattern");
        let (perm_fwd, perm_inv): (Vec<usize>, Vec<usize>) = match ordered.perm() {
            Some(p) => {
                let (fwd, inv) = p.arrays();
                (fwd.to_vec(), inv.to_vec())
            }
            None => ((0..dim).collect(), (0..dim).collect()),
        };
        // …applied once to the pattern (step 4). faer's symbolic analysis without an ordering
        // reads the upper triangle; the numeric factorization is given the lower one.
        for e in &mut entries {
            let (r, c) = (perm_inv[e.0], perm_inv[e.1]);
            (e.0, e.1) = (r.min(c), r.max(c));
        }
        sort_by_column(&mut entries, &mut sorted, dim);
        let (col_ptr, row_idx, _) = csc_pattern(dim, &entries, nb);
        let symbolic_a = SymbolicSparseColMatRef::new_checked(dim, dim, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            symbolic_a,
            Side::Upper,
            SymmetricOrdering::Identity,
            params,
        )
        .expect("symbolic Cholesky of a small mesh pattern");
        for e in &mut entries {
            (e.0, e.1) = (e.1, e.0);
        }
        sort_by_column(&mut entries, &mut sorted, dim);
        let (col_ptr, row_idx, scatter) = csc_pattern(dim, &entries, nb);
        debug_assert_eq!(
            symbolic.len_val(),
            ordered.len_val(),
            "same fill as faer's AMD"
        );
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, supernode_llt_params()),
            symbolic.solve_in_place_scratch::<f64>(LOW_RANK_CAPACITY, Par::Seq),
            faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
                LOW_RANK_CAPACITY,
                Par::Seq,
                Default::default(),
            ),
        ]);
        let mem = MemBuffer::new(req);
        let l_values = vec![0.0; symbolic.len_val()];
        let mut sys = Self {
            n,
            off_pairs,
            blocks: vec![M3::zeros(); nb],
            values: vec![0.0; row_idx.len()],
            pattern: SymbolicSparseColMat::new_checked(dim, dim, col_ptr, None, row_idx),
            scatter,
            symbolic,
            l_values,
            mem,
            rhs: vec![0.0; dim],
            permuted_rhs: vec![0.0; dim],
            perm_fwd,
            perm_inv,
            low_rank: Vec::with_capacity(LOW_RANK_CAPACITY),
            low_rank_limit: LOW_RANK_CAPACITY,
            lr_z: vec![0.0; dim * LOW_RANK_CAPACITY],
            lr_cap: vec![0.0; LOW_RANK_CAPACITY * LOW_RANK_CAPACITY],
            lr_t: vec![0.0; LOW_RANK_CAPACITY],
            factorizations: 0,
            factored: false,
            factored_p: 0,
        };
        if !THREAD_WARM.with(Cell::get) {
            sys.warm_up();
            THREAD_WARM.with(|w| w.set(true));
        }
        sys
    }

    /// Runs every dense kernel of the factorization and the solve once, on the current thread.
    /// The first numeric factorization of the process initialises lazily computed CPU data of
    /// the dense kernels (cache sizes, read from /sys), and the first large dense product on a
    /// thread the product's packing memory (kept per thread, its size fixed by the cache
    /// sizes): both allocate. Done by the first system built on a thread, where allocating is
    /// allowed, so that no step on it ever does (a thread that steps a sheet built elsewhere
    /// calls [`warm_up_thread`] first). The values are overwritten by the first real
    /// factorization.
    fn warm_up(&mut self) {
        let n = self.n;
        let ones = vec![1.0; n];
        let free = vec![false; n];
        self.clear();
        for i in 0..n {
            self.add_diag(i as u32, &M3::identity());
        }
        // …the Woodbury path…
        if n > 0 {
            self.add_rank_one(
                &[0; 4],
                &[1.0, 0.0, 0.0, 0.0],
                &nalgebra::Vector3::x(),
                1.0,
                &free,
            );
        }
        let _ = self.factorize_and_solve(&free, &ones, 0.0);
        // …and a dense product above faer's small-size threshold (16³), which takes the
        // packing kernels: the Woodbury products reach that size with a few contact pairs, the
        // supernodes of a large mesh too, the single term above does not.
        let k = 17;
        let (a, mut c) = (vec![1.0; k * k], vec![0.0; k * k]);
        let am = faer::MatRef::from_column_major_slice(&a, k, k);
        matmul(
            MatMut::from_column_major_slice_mut(&mut c, k, k),
            Accum::Replace,
            am,
            am,
            1.0,
            Par::Seq,
        );
        self.low_rank.clear();
        self.factorizations = 0;
        self.factored = false;
        self.factored_p = 0;
        self.rhs.iter_mut().for_each(|r| *r = 0.0);
    }

    /// Rank-one terms held.
    pub fn low_rank_len(&self) -> usize {
        self.low_rank.len()
    }

    /// Sets how many rank-one terms [`Self::add_rank_one`] accepts (at most
    /// [`LOW_RANK_CAPACITY`]).
    pub fn set_low_rank_limit(&mut self, limit: usize) {
        self.low_rank_limit = limit.min(LOW_RANK_CAPACITY);
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.n
    }

    /// Number of stored (upper-triangle) scalar non-zeros.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Number of non-zeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    /// Block index of the pair `(i, j)` (`i != j`) and whether the stored block is the
    /// transpose of the `(i, j)` block (i.e. `i > j`).
    ///
    /// # Panics
    /// Panics if the pair is not in the pattern.
    pub fn off_block(&self, i: u32, j: u32) -> (u32, bool) {
        let key = [i.min(j), i.max(j)];
        let k = self
            .off_pairs
            .binary_search(&key)
            .expect("vertex pair not in the block pattern");
        ((self.n + k) as u32, i > j)
    }

    /// Zeroes all blocks and drops the rank-one terms.
    pub fn clear(&mut self) {
        for b in &mut self.blocks {
            *b = M3::zeros();
        }
        self.low_rank.clear();
    }

    /// Adds the rank-one term `c (w ⊗ n)(w ⊗ n)ᵀ` (c ≥ 0) coupling up to four vertices that
    /// need not share a block of the pattern; vertices with `skip[v]` are left out (their
    /// rows are decoupled anyway). Returns false, adding nothing, when
    /// [`LOW_RANK_CAPACITY`] terms are held already.
    pub fn add_rank_one(
        &mut self,
        v: &[u32; 4],
        w: &[f64; 4],
        n: &nalgebra::Vector3<f64>,
        c: f64,
        skip: &[bool],
    ) -> bool {
        if self.low_rank.len() >= self.low_rank_limit {
            return false;
        }
        let s = c.max(0.0).sqrt();
        let mut u = [(0u32, 0.0); 12];
        let mut len = 0;
        for (&vi, &wi) in v.iter().zip(w) {
            if skip[vi as usize] || wi == 0.0 {
                continue;
            }
            for k in 0..3 {
                let val = s * wi * n[k];
                if val != 0.0 {
                    u[len] = (self.perm_inv[3 * vi as usize + k] as u32, val);
                    len += 1;
                }
            }
        }
        // Unused slots stay (0, 0.0): they add nothing.
        self.low_rank.push(u);
        true
    }

    /// Adds `m` to the (i, j) block given a precomputed `(block, transposed)` from
    /// [`Self::off_block`].
    #[inline]
    pub fn add_off(&mut self, block: (u32, bool), m: &M3) {
        let b = &mut self.blocks[block.0 as usize];
        if block.1 {
            *b += m.transpose();
        } else {
            *b += m;
        }
    }

    /// Adds `m` to the diagonal block of vertex `i`.
    #[inline]
    pub fn add_diag(&mut self, i: u32, m: &M3) {
        self.blocks[i as usize] += m;
    }

    /// Scatters the blocks into the CSC values. Rows and columns of `fixed` vertices become
    /// `diag_fixed[i] · I` (decoupled); free vertices get `reg · diag_fixed[i]` added to their
    /// diagonal (Levenberg–Marquardt damping).
    fn scatter(&mut self, fixed: &[bool], diag_fixed: &[f64], reg: f64) {
        for i in 0..self.n {
            let b = &self.blocks[i];
            let s = &self.scatter[i];
            for r in 0..3 {
                for c in r..3 {
                    let v = if fixed[i] {
                        if r == c { diag_fixed[i] } else { 0.0 }
                    } else if r == c {
                        b[(r, c)] + reg * diag_fixed[i]
                    } else {
                        0.5 * (b[(r, c)] + b[(c, r)])
                    };
                    self.values[s[r * 3 + c] as usize] = v;
                }
            }
        }
        for (k, p) in self.off_pairs.iter().enumerate() {
            let bi = self.n + k;
            let zero = fixed[p[0] as usize] || fixed[p[1] as usize];
            let b = &self.blocks[bi];
            let s = &self.scatter[bi];
            for r in 0..3 {
                for c in 0..3 {
                    self.values[s[r * 3 + c] as usize] = if zero { 0.0 } else { b[(r, c)] };
                }
            }
        }
    }

    /// Assembles, factorizes and solves `A x = rhs` in place (`self.rhs` holds the solution on
    /// success). `fixed` rows are decoupled (their solution is `rhs / diag_fixed`); `reg`
    /// adds `reg · diag_fixed` to the diagonal of the free rows.
    pub fn factorize_and_solve(
        &mut self,
        fixed: &[bool],
        diag_fixed: &[f64],
        reg: f64,
    ) -> Result<(), SolveError> {
        self.factored = false;
        self.scatter(fixed, diag_fixed, reg);
        let dim = 3 * self.n;
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        let stack = MemStack::new(&mut self.mem);
        self.factorizations += 1;
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                a,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                stack,
                supernode_llt_params(),
            )
            .map_err(|_| SolveError::NotPositiveDefinite)?;
        let p = self.low_rank.len();
        self.factored_p = 0;
        if p > 0 {
            let split = match (self.symbolic.raw(), self.symbolic.perm()) {
                (SymbolicCholeskyRaw::Supernodal(sym), None) => {
                    Some(SupernodalLltRef::new(sym, &self.l_values))
                }
                _ => None,
            };
            let Some(l) = split else {
                // An unsplit factor cannot happen with the forced supernodal, unordered
                // analysis of `new`; the coupling is dropped rather than solved wrongly.
                self.low_rank.clear();
                self.factored = true;
                self.solve_factored();
                return Ok(());
            };
            // Woodbury on the split factor A = L Lᵀ (module doc, step 5):
            // W = L⁻¹ U, C = I + Wᵀ W, factorized once per factorization.
            let w = &mut self.lr_z[..dim * p];
            w.iter_mut().for_each(|v| *v = 0.0);
            for (col, u) in self.low_rank.iter().enumerate() {
                for &(i, val) in u {
                    w[col * dim + i as usize] += val;
                }
            }
            let wm = MatMut::from_column_major_slice_mut(w, dim, p);
            l.l_solve_with_conj(Conj::No, wm, Par::Seq, MemStack::new(&mut self.mem));
            let w = faer::MatRef::from_column_major_slice(&self.lr_z[..dim * p], dim, p);
            let cap = &mut self.lr_cap[..p * p];
            let mut cm = MatMut::from_column_major_slice_mut(cap, p, p);
            matmul(&mut cm, Accum::Replace, w.transpose(), w, 1.0, Par::Seq);
            for k in 0..p {
                cm[(k, k)] += 1.0;
            }
            faer::linalg::cholesky::llt::factor::cholesky_in_place(
                MatMut::from_column_major_slice_mut(cap, p, p),
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .map_err(|_| SolveError::NotPositiveDefinite)?;
            self.factored_p = p;
        }
        self.factored = true;
        self.solve_factored();
        Ok(())
    }

    /// Solves `rhs` in place again with the matrix of the last successful
    /// [`Self::factorize_and_solve`] (its factor and rank-one terms), whatever has been
    /// assembled since. Returns false, leaving `rhs` as it is, if there is no such factor.
    pub fn solve_again(&mut self) -> bool {
        if !self.factored {
            return false;
        }
        self.solve_factored();
        true
    }

    /// `rhs ← A⁻¹ rhs` with the current factor and the factorized Woodbury terms.
    fn solve_factored(&mut self) {
        let dim = 3 * self.n;
        for (y, &k) in self.permuted_rhs.iter_mut().zip(&self.perm_fwd) {
            *y = self.rhs[k];
        }
        let p = self.factored_p;
        // The factor's supernodes, to solve with L and Lᵀ separately (the pattern is stored
        // permuted, so faer's factor has no ordering of its own).
        let split = if p > 0 {
            match (self.symbolic.raw(), self.symbolic.perm()) {
                (SymbolicCholeskyRaw::Supernodal(sym), None) => {
                    Some(SupernodalLltRef::new(sym, &self.l_values))
                }
                _ => None,
            }
        } else {
            None
        };
        if let Some(l) = split {
            // x = L⁻ᵀ (y − W C⁻¹ Wᵀ y), y = L⁻¹ b.
            let y = MatMut::from_column_major_slice_mut(&mut self.permuted_rhs, dim, 1);
            l.l_solve_with_conj(Conj::No, y, Par::Seq, MemStack::new(&mut self.mem));
            let w = faer::MatRef::from_column_major_slice(&self.lr_z[..dim * p], dim, p);
            let y = faer::MatRef::from_column_major_slice(&self.permuted_rhs, dim, 1);
            let t = MatMut::from_column_major_slice_mut(&mut self.lr_t[..p], p, 1);
            matmul(t, Accum::Replace, w.transpose(), y, 1.0, Par::Seq);
            faer::linalg::cholesky::llt::solve::solve_in_place_with_conj(
                faer::MatRef::from_column_major_slice(&self.lr_cap[..p * p], p, p),
                Conj::No,
                MatMut::from_column_major_slice_mut(&mut self.lr_t[..p], p, 1),
                Par::Seq,
                MemStack::new(&mut self.mem),
            );
            let s = faer::MatRef::from_column_major_slice(&self.lr_t[..p], p, 1);
            let y = MatMut::from_column_major_slice_mut(&mut self.permuted_rhs, dim, 1);
            matmul(y, Accum::Add, w, s, -1.0, Par::Seq);
            let y = MatMut::from_column_major_slice_mut(&mut self.permuted_rhs, dim, 1);
            l.l_transpose_solve_with_conj(Conj::No, y, Par::Seq, MemStack::new(&mut self.mem));
        } else {
            let llt = LltRef::new(&self.symbolic, &self.l_values);
            let rhs = MatMut::from_column_major_slice_mut(&mut self.permuted_rhs, dim, 1);
            let stack = MemStack::new(&mut self.mem);
            llt.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
        }
        for (&y, &k) in self.permuted_rhs.iter().zip(&self.perm_fwd) {
            self.rhs[k] = y;
        }
    }
}

/// Sorts scalar entries `(row, col, block, entry)` by column, then row: two stable counting
/// sorts (by row, then by column; every index is below `dim`), a radix sort. It gives the
/// order of a comparison sort on (col, row) in a fraction of its time: rebuilding the system
/// is part of every vertex insertion's frame (`cargo bench -p sim-core --bench step --
/// rebuild`). `scratch` is reused between calls.
fn sort_by_column(
    entries: &mut Vec<(usize, usize, u32, u8)>,
    scratch: &mut Vec<(usize, usize, u32, u8)>,
    dim: usize,
) {
    let mut next = vec![0usize; dim + 1];
    scratch.clear();
    scratch.resize(entries.len(), (0, 0, 0, 0));
    for key in [
        |e: &(usize, usize, u32, u8)| e.0,
        |e: &(usize, usize, u32, u8)| e.1,
    ] {
        next.iter_mut().for_each(|c| *c = 0);
        for e in entries.iter() {
            next[key(e) + 1] += 1;
        }
        for k in 0..dim {
            next[k + 1] += next[k];
        }
        for e in entries.iter() {
            let slot = &mut next[key(e)];
            scratch[*slot] = *e;
            *slot += 1;
        }
        std::mem::swap(entries, scratch);
    }
}

/// CSC column pointers, row indices and the block-entry → value-slot map of `entries`
/// `(row, col, block, entry)` sorted by column then row.
fn csc_pattern(
    dim: usize,
    entries: &[(usize, usize, u32, u8)],
    num_blocks: usize,
) -> (Vec<usize>, Vec<usize>, Vec<[u32; 9]>) {
    let mut col_ptr = vec![0usize; dim + 1];
    let mut row_idx = Vec::with_capacity(entries.len());
    let mut scatter = vec![[NO_SLOT; 9]; num_blocks];
    for (slot, e) in entries.iter().enumerate() {
        col_ptr[e.1 + 1] += 1;
        row_idx.push(e.0);
        scatter[e.2 as usize][e.3 as usize] = slot as u32;
    }
    for c in 0..dim {
        col_ptr[c + 1] += col_ptr[c];
    }
    (col_ptr, row_idx, scatter)
}

/// Columns below which faer's dense Cholesky of a supernode's diagonal block stops recursing
/// (module doc, step 6).
pub const SUPERNODE_RECURSION_COLS: usize = 16;

/// faer's Cholesky parameters for the numeric factorization (module doc, step 6).
fn supernode_llt_params() -> faer::Spec<LltParams, f64> {
    LltParams {
        recursion_threshold: SUPERNODE_RECURSION_COLS,
        ..<LltParams as faer::Auto<f64>>::auto()
    }
    .into()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A system on `pairs` with diagonal blocks `diag(i)·I` and every off-diagonal block `off`,
    /// and the same matrix dense.
    fn system_and_dense(
        n: usize,
        pairs: &[[u32; 2]],
        diag: impl Fn(usize) -> f64,
        off: M3,
    ) -> (BlockSystem, nalgebra::DMatrix<f64>) {
        let mut s = BlockSystem::new(n, pairs.iter().copied());
        s.clear();
        let mut dense = nalgebra::DMatrix::<f64>::zeros(3 * n, 3 * n);
        for i in 0..n {
            let d = M3::identity() * diag(i);
            s.add_diag(i as u32, &d);
            dense.view_mut((3 * i, 3 * i), (3, 3)).copy_from(&d);
        }
        for p in pairs {
            s.add_off(s.off_block(p[0], p[1]), &off);
            let (i, j) = (3 * p[0] as usize, 3 * p[1] as usize);
            dense.view_mut((i, j), (3, 3)).copy_from(&off);
            dense.view_mut((j, i), (3, 3)).copy_from(&off.transpose());
        }
        (s, dense)
    }

    /// The dense rank-one term c (w ⊗ n)(w ⊗ n)ᵀ of `BlockSystem::add_rank_one`, without the
    /// vertices marked in `skip`.
    fn dense_term(
        dim: usize,
        v: &[u32; 4],
        w: &[f64; 4],
        nrm: &nalgebra::Vector3<f64>,
        c: f64,
        skip: &[bool],
    ) -> nalgebra::DMatrix<f64> {
        let mut u = nalgebra::DVector::<f64>::zeros(dim);
        for (&vi, &wi) in v.iter().zip(w) {
            if !skip[vi as usize] {
                for r in 0..3 {
                    u[3 * vi as usize + r] += c.sqrt() * wi * nrm[r];
                }
            }
        }
        &u * u.transpose()
    }

    #[test]
    fn solves_a_small_spd_chain_and_decouples_fixed_rows() {
        // 4 vertices in a chain: blocks (0,1), (1,2), (2,3).
        let n = 4;
        let mut s = BlockSystem::new(n, [[0, 1], [2, 1], [2, 3], [3, 2]]);
        s.clear();
        for i in 0..n as u32 {
            s.add_diag(i, &(M3::identity() * 4.0));
        }
        let off = M3::new(-1.0, 0.2, 0.0, 0.1, -1.0, 0.0, 0.0, 0.0, -1.0);
        for (i, j) in [(0u32, 1u32), (2, 1), (2, 3)] {
            let b = s.off_block(i, j);
            s.add_off(b, &off);
        }
        // Dense reference.
        let mut dense = nalgebra::DMatrix::<f64>::zeros(12, 12);
        for i in 0..4 {
            dense
                .view_mut((3 * i, 3 * i), (3, 3))
                .copy_from(&(M3::identity() * 4.0));
        }
        for (i, j) in [(0usize, 1usize), (2, 1), (2, 3)] {
            dense.view_mut((3 * i, 3 * j), (3, 3)).copy_from(&off);
            dense
                .view_mut((3 * j, 3 * i), (3, 3))
                .copy_from(&off.transpose());
        }
        let rhs: Vec<f64> = (0..12).map(|k| (k as f64 * 0.37).sin()).collect();
        s.rhs.copy_from_slice(&rhs);
        let fixed = vec![false; n];
        s.factorize_and_solve(&fixed, &[1.0; 4], 0.0).unwrap();
        let x = nalgebra::DVector::from_column_slice(&s.rhs);
        let r = &dense * &x - nalgebra::DVector::from_column_slice(&rhs);
        assert!(r.norm() < 1e-12, "residual {}", r.norm());

        // Fix vertex 1: its rows decouple; the rest is the reduced system.
        let fixed = vec![false, true, false, false];
        s.rhs.copy_from_slice(&rhs);
        s.factorize_and_solve(&fixed, &[1.0, 2.0, 1.0, 1.0], 0.0)
            .unwrap();
        for c in 0..3 {
            assert!((s.rhs[3 + c] - rhs[3 + c] / 2.0).abs() < 1e-14);
        }
        assert_eq!(s.factorizations, 2);
    }

    /// Rank-one terms between vertices that share no block (the solve's Woodbury term) give
    /// the solution of the dense matrix with the terms added; a skipped (fixed) vertex is left
    /// out of them, and terms beyond the limit are refused.
    #[test]
    fn the_column_sort_orders_like_a_comparison_sort() {
        // Distinct (row, col) pairs in a scrambled order, with their origin tags.
        let dim = 37;
        let mut entries: Vec<(usize, usize, u32, u8)> = (0..dim * dim)
            .filter(|k| (k * 7919) % 5 != 0)
            .map(|k| {
                let k = (k * 7919) % (dim * dim);
                (k % dim, k / dim, k as u32, (k % 9) as u8)
            })
            .collect();
        let mut expected = entries.clone();
        expected.sort_unstable_by_key(|e| (e.1, e.0));
        let mut scratch = Vec::new();
        sort_by_column(&mut entries, &mut scratch, dim);
        assert_eq!(entries, expected);
        assert!(entries.len() > dim * dim / 2);
    }

    #[test]
    fn many_rank_one_terms_on_a_grid_solve_like_the_dense_matrix() {
        // A 10 × 10 grid of vertices with 40 terms coupling far-apart vertices: the factor has
        // many supernodes and the Woodbury products (40 × 40 × 300) take faer's large kernels.
        let side = 10;
        let n = side * side;
        let mut pairs = Vec::new();
        for y in 0..side {
            for x in 0..side {
                let v = (y * side + x) as u32;
                if x + 1 < side {
                    pairs.push([v, v + 1]);
                }
                if y + 1 < side {
                    pairs.push([v, v + side as u32]);
                }
            }
        }
        let off = M3::new(-1.0, 0.1, 0.0, 0.1, -0.9, 0.1, 0.0, 0.1, -1.0) * 0.5;
        let (mut s, mut dense) = system_and_dense(n, &pairs, |i| 5.0 + (i % 7) as f64 * 0.1, off);
        let fixed = vec![false; n];
        let base = dense.clone();
        let mut state = 12345u64;
        let mut next = |m: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % m
        };
        for _ in 0..40 {
            let v = [0; 4].map(|_| next(n as u64) as u32);
            let w = [1.0, -0.4, -0.35, -0.25];
            let nrm = nalgebra::Vector3::new(0.3, -0.5, 0.8).normalize();
            let c = 10.0 + next(50) as f64;
            assert!(s.add_rank_one(&v, &w, &nrm, c, &fixed));
            dense += dense_term(3 * n, &v, &w, &nrm, c, &fixed);
        }
        let rhs: Vec<f64> = (0..3 * n).map(|k| (k as f64 * 0.37).sin()).collect();
        s.rhs.copy_from_slice(&rhs);
        s.factorize_and_solve(&fixed, &vec![1.0; n], 0.0).unwrap();
        let x = nalgebra::DVector::from_column_slice(&s.rhs);
        let b = nalgebra::DVector::from_column_slice(&rhs);
        let r = &dense * &x - &b;
        assert!(r.norm() < 1e-10 * b.norm(), "residual {}", r.norm());
        // The terms change the answer (so the check above can fail).
        let without = base.cholesky().unwrap().solve(&b);
        assert!((&x - &without).norm() > 0.01 * without.norm());
    }

    #[test]
    fn rank_one_terms_solve_like_the_dense_matrix() {
        let n = 6;
        let chain: Vec<[u32; 2]> = (0..n as u32 - 1).map(|i| [i, i + 1]).collect();
        let off = M3::new(-1.0, 0.1, 0.0, 0.2, -0.9, 0.1, 0.0, 0.0, -1.0) * 0.5;
        let (mut s, mut dense) = system_and_dense(n, &chain, |i| 3.0 + i as f64 * 0.1, off);
        // Vertex 4 is fixed: its rows decouple.
        let fixed = [false, false, false, false, true, false];
        let terms: [([u32; 4], [f64; 4], nalgebra::Vector3<f64>, f64); 3] = [
            (
                [0, 3, 5, 2],
                [1.0, -0.5, -0.3, -0.2],
                nalgebra::Vector3::new(0.0, 0.6, 0.8),
                40.0,
            ),
            (
                [1, 4, 5, 0],
                [0.7, 0.3, -0.4, -0.6],
                nalgebra::Vector3::new(1.0, 0.0, 0.0),
                25.0,
            ),
            (
                [2, 5, 0, 1],
                [1.0, -1.0, 0.0, 0.0],
                nalgebra::Vector3::new(0.0, 0.0, 1.0),
                10.0,
            ),
        ];
        // The pattern matrix alone, to show below that the terms change the answer.
        let mut base = dense.clone();
        s.set_low_rank_limit(2);
        for (k, (v, w, nrm, c)) in terms.iter().enumerate() {
            let added = s.add_rank_one(v, w, nrm, *c, &fixed);
            assert_eq!(added, k < 2);
            if !added {
                continue;
            }
            dense += dense_term(3 * n, v, w, nrm, *c, &fixed);
        }
        assert_eq!(s.low_rank_len(), 2);
        // The fixed vertex: identity-scaled row and column.
        for m in [&mut dense, &mut base] {
            for r in 0..3 * n {
                for c in 12..15 {
                    m[(r, c)] = 0.0;
                    m[(c, r)] = 0.0;
                }
            }
            for c in 12..15 {
                m[(c, c)] = 2.0;
            }
        }
        let diag_fixed = [1.0, 1.0, 1.0, 1.0, 2.0, 1.0];
        let rhs: Vec<f64> = (0..3 * n).map(|k| (k as f64 * 0.71).cos()).collect();
        s.rhs.copy_from_slice(&rhs);
        s.factorize_and_solve(&fixed, &diag_fixed, 0.0).unwrap();
        let x = nalgebra::DVector::from_column_slice(&s.rhs);
        let r = &dense * &x - nalgebra::DVector::from_column_slice(&rhs);
        assert!(r.norm() < 1e-12, "residual {}", r.norm());
        // The terms matter: the pattern matrix alone leaves a large residual (the test can fail).
        let r0 = &base * &x - nalgebra::DVector::from_column_slice(&rhs);
        assert!(r0.norm() > 1e-2, "residual without the terms {}", r0.norm());
        s.clear();
        assert_eq!(s.low_rank_len(), 0);
        // The factor stays: a new right-hand side solves with the same matrix, terms
        // included, whatever was assembled since (the blocks were just cleared).
        let rhs2: Vec<f64> = (0..3 * n).map(|k| (k as f64 * 1.3).sin() + 0.2).collect();
        s.rhs.copy_from_slice(&rhs2);
        assert!(s.solve_again());
        let x2 = nalgebra::DVector::from_column_slice(&s.rhs);
        let r2 = &dense * &x2 - nalgebra::DVector::from_column_slice(&rhs2);
        assert!(
            r2.norm() < 1e-12,
            "residual of the reused factor {}",
            r2.norm()
        );
    }

    #[test]
    fn solve_again_needs_a_successful_factorization() {
        let n = 3;
        let chain = [[0u32, 1], [1, 2]];
        let (mut s, _) = system_and_dense(n, &chain, |_| 2.0, M3::identity() * -0.5);
        let free = [false; 3];
        let ones = [1.0; 3];
        s.rhs.iter_mut().for_each(|r| *r = 1.0);
        assert!(!s.solve_again(), "no factorization yet");
        assert!(s.rhs.iter().all(|&r| r == 1.0), "rhs untouched");
        s.factorize_and_solve(&free, &ones, 0.0).unwrap();
        let first = s.rhs.clone();
        s.rhs.iter_mut().for_each(|r| *r = 1.0);
        assert!(s.solve_again());
        assert_eq!(s.rhs, first, "the same factor gives the same bits");
        // An indefinite matrix fails to factorize, and its failure leaves no factor behind.
        s.clear();
        for i in 0..n as u32 {
            s.add_diag(i, &(M3::identity() * -1.0));
        }
        assert!(s.factorize_and_solve(&free, &ones, 0.0).is_err());
        assert!(!s.solve_again());
    }
}
