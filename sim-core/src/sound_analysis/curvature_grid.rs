//! # The curvature grid and crumple-event detection (T 1772, S 126; digest-sound §2.2)
//!
//! The seeds sample the mean curvature on a regular grid "projected onto the surface" because
//! their mesh is remeshed all the time (thesis Fig. 4.10). Here the grid is regular in the
//! *pattern* (material coordinates): grid point (i, j) sits at the centre of cell (i, j) of the
//! sheet's rectangle, so it is the same piece of paper in every frame, however S_P is remeshed.
//! Each frame every grid point is located in the S_P triangle that covers it in the pattern
//! (each triangle rasterizes its pattern bounding box; linear in the number of grid points)
//! and its mean curvature is the barycentric interpolation of the vertex values H_v.
//! The location depends only on S_P's pattern and triangles, which change only at mesh events
//! (a vertex insertion, a flip, a pattern vertex moved under a hand), so
//! it is kept with a copy of both and redone only when either differs: the same grid points in
//! the same triangles with the same weights, at a fraction of the cost in the frames between
//! (the rasterization was 1.6 % of a C5 frame, `perf`).
//!
//! A grid point flips when its confident curvature sign changes (see the module doc of
//! [`crate::sound_analysis`] for the comparison with the last confident value) with
//! |H − H_ref| > ε_H. Flipped points with the same direction (+→− or −→+) that are 4-connected
//! form one crumple event; its amplitude is Σ Δ_v over the event (scaled by the cell area by
//! the caller), and the S_P triangles under its points seed the resonator search.

use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;

use super::AnalysisConfig;
use super::curvature::Curvature;

/// One crumple event of the grid.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridEvent {
    /// Σ |ΔH| over the event's points, 1/m.
    pub sum_delta: f64,
    /// Number of grid points.
    pub num_points: u32,
    /// +1 for a −→+ flip, −1 for +→−.
    pub direction: i8,
    first_tri: u32,
    num_tris: u32,
}

/// Result of one detection pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FlipSummary {
    /// Grid points that flipped.
    pub flipped_points: u32,
}

/// Upper bound on events per frame (more are merged into the last, never lost).
pub const MAX_GRID_EVENTS: usize = 64;

/// The grid and its per-point history.
#[derive(Clone, Debug)]
pub struct CurvatureGrid {
    spacing_target_m: f64,
    nx: usize,
    ny: usize,
    hx: f64,
    hy: f64,
    x0: f64,
    y0: f64,
    tri: Vec<u32>,
    bary: Vec<[f32; 3]>,
    /// The pattern and triangles `tri` and `bary` were located on (empty: not located).
    located_pattern: Vec<crate::math::V2>,
    located_triangles: Vec<[u32; 3]>,
    h: Vec<f32>,
    h_ref: Vec<f32>,
    last_flip_s: Vec<f64>,
    flip: Vec<i8>,
    delta: Vec<f32>,
    label: Vec<u32>,
    stack: Vec<u32>,
    events: Vec<GridEvent>,
    event_tris: Vec<u32>,
}

impl CurvatureGrid {
    /// A grid with buffers large enough for a sheet of `max_sheet_m` at `spacing_m`.
    /// `max_vertices` and `max_triangles` size the copy of the mesh the location was made on.
    pub fn with_capacity(
        spacing_m: f64,
        max_sheet_m: (f64, f64),
        max_vertices: usize,
        max_triangles: usize,
    ) -> Self {
        let spacing = if spacing_m.is_finite() && spacing_m > 1e-3 {
            spacing_m
        } else {
            0.01
        };
        let cap = ((max_sheet_m.0 / spacing).ceil() as usize + 1)
            * ((max_sheet_m.1 / spacing).ceil() as usize + 1);
        Self {
            spacing_target_m: spacing,
            nx: 0,
            ny: 0,
            hx: spacing,
            hy: spacing,
            x0: 0.0,
            y0: 0.0,
            tri: Vec::with_capacity(cap),
            bary: Vec::with_capacity(cap),
            located_pattern: Vec::with_capacity(max_vertices),
            located_triangles: Vec::with_capacity(max_triangles),
            h: Vec::with_capacity(cap),
            h_ref: Vec::with_capacity(cap),
            last_flip_s: Vec::with_capacity(cap),
            flip: Vec::with_capacity(cap),
            delta: Vec::with_capacity(cap),
            label: Vec::with_capacity(cap),
            stack: Vec::with_capacity(cap),
            events: Vec::with_capacity(MAX_GRID_EVENTS),
            event_tris: Vec::with_capacity(cap),
        }
    }

    /// Lays the grid over a `width_m` × `length_m` sheet centred on the pattern origin and
    /// forgets the history.
    pub fn resize(&mut self, width_m: f64, length_m: f64) {
        let s = self.spacing_target_m;
        self.nx = ((width_m / s).round() as usize).max(1);
        self.ny = ((length_m / s).round() as usize).max(1);
        self.hx = width_m / self.nx as f64;
        self.hy = length_m / self.ny as f64;
        self.x0 = -0.5 * width_m + 0.5 * self.hx;
        self.y0 = -0.5 * length_m + 0.5 * self.hy;
        let n = self.nx * self.ny;
        for v in [&mut self.h, &mut self.h_ref, &mut self.delta] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.last_flip_s.clear();
        self.last_flip_s.resize(n, f64::NEG_INFINITY);
        self.tri.clear();
        self.tri.resize(n, NONE);
        self.bary.clear();
        self.bary.resize(n, [0.0; 3]);
        self.located_pattern.clear();
        self.located_triangles.clear();
        self.flip.clear();
        self.flip.resize(n, 0);
        self.label.clear();
        self.label.resize(n, NONE);
        self.events.clear();
        self.event_tris.clear();
    }

    /// Columns and rows.
    pub fn dims(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Grid spacing along x and y, metres.
    pub fn spacing_m(&self) -> (f64, f64) {
        (self.hx, self.hy)
    }

    /// Curvature of the grid points after the last [`Self::sample`], 1/m.
    pub fn curvature(&self) -> &[f32] {
        &self.h
    }

    /// The memory between frames: each point's last confident curvature (1/m, 0 = none yet)
    /// and the time of its last flip (s, −∞ = never).
    pub fn history(&self) -> (&[f32], &[f64]) {
        (&self.h_ref, &self.last_flip_s)
    }

    /// Restores [`Self::history`] on a grid of the same dimensions. Returns an error message
    /// (and changes nothing) if the lengths do not fit the grid or a value is not finite
    /// (−∞ is "never" for a flip time).
    pub fn restore_history(&mut self, h_ref: &[f32], last_flip_s: &[f64]) -> Result<(), String> {
        let n = self.nx * self.ny;
        if h_ref.len() != n || last_flip_s.len() != n {
            return Err(format!(
                "sound history has {} and {} grid points, the grid has {n}",
                h_ref.len(),
                last_flip_s.len()
            ));
        }
        if let Some(k) = h_ref.iter().position(|h| !h.is_finite()) {
            return Err(format!(
                "sound history: curvature of grid point {k} is not finite"
            ));
        }
        if let Some(k) = last_flip_s
            .iter()
            .position(|t| !(t.is_finite() || *t == f64::NEG_INFINITY))
        {
            return Err(format!(
                "sound history: flip time of grid point {k} is not finite"
            ));
        }
        self.h_ref.copy_from_slice(h_ref);
        self.last_flip_s.copy_from_slice(last_flip_s);
        Ok(())
    }

    /// Locates every grid point in S_P and interpolates the vertex mean curvature.
    pub fn sample(&mut self, sp: &PhysMesh, curv: &Curvature) {
        let located = !self.located_triangles.is_empty()
            && self.located_triangles == sp.triangles
            && self.located_pattern == sp.pattern;
        if !located {
            self.locate(sp);
        }
        for k in 0..self.h.len() {
            let t = self.tri[k];
            self.h[k] = if t == NONE {
                0.0
            } else {
                let tri = sp.triangles[t as usize];
                let w = self.bary[k];
                let hv = |i: usize| curv.vertex_h_per_m[tri[i] as usize] as f32;
                w[0] * hv(0) + w[1] * hv(1) + w[2] * hv(2)
            };
        }
    }

    /// Finds the S_P triangle and barycentric weights of every grid point, and keeps the mesh
    /// it found them on.
    fn locate(&mut self, sp: &PhysMesh) {
        self.located_pattern.clone_from(&sp.pattern);
        self.located_triangles.clone_from(&sp.triangles);
        for t in &mut self.tri {
            *t = NONE;
        }
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        for (t, tri) in sp.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| sp.pattern[i as usize]);
            let det = (b - a).perp(&(c - a));
            if det.abs() < 1e-18 {
                continue;
            }
            let (minx, maxx) = (a.x.min(b.x).min(c.x), a.x.max(b.x).max(c.x));
            let (miny, maxy) = (a.y.min(b.y).min(c.y), a.y.max(b.y).max(c.y));
            let i0 = (((minx - self.x0) / self.hx).floor() as i64).clamp(0, nx - 1);
            let i1 = (((maxx - self.x0) / self.hx).ceil() as i64).clamp(0, nx - 1);
            let j0 = (((miny - self.y0) / self.hy).floor() as i64).clamp(0, ny - 1);
            let j1 = (((maxy - self.y0) / self.hy).ceil() as i64).clamp(0, ny - 1);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let k = (j * nx + i) as usize;
                    if self.tri[k] != NONE {
                        continue;
                    }
                    let p = crate::math::V2::new(
                        self.x0 + i as f64 * self.hx,
                        self.y0 + j as f64 * self.hy,
                    );
                    let wb = (p - a).perp(&(c - a)) / det;
                    let wc = (b - a).perp(&(p - a)) / det;
                    let wa = 1.0 - wb - wc;
                    const TOL: f64 = -1e-9;
                    if wa >= TOL && wb >= TOL && wc >= TOL {
                        self.tri[k] = t as u32;
                        self.bary[k] = [wa as f32, wb as f32, wc as f32];
                    }
                }
            }
        }
    }

    /// Finds the flipped points and groups them into events.
    pub fn detect_flips(&mut self, cfg: &AnalysisConfig, time_s: f64) -> FlipSummary {
        let conf = cfg.confident_curvature_per_m as f32;
        let eps = cfg.flip_threshold_per_m as f32;
        let mut flipped = 0u32;
        for k in 0..self.h.len() {
            self.flip[k] = 0;
            self.delta[k] = 0.0;
            let h = self.h[k];
            if self.tri[k] == NONE || !h.is_finite() || h.abs() <= conf {
                continue;
            }
            let r = self.h_ref[k];
            if r != 0.0 && r.signum() != h.signum() && (h - r).abs() > eps {
                if time_s - self.last_flip_s[k] < cfg.refractory_s {
                    // Still ringing from its last flip: the new sign is taken, silently.
                    self.h_ref[k] = h;
                    continue;
                }
                self.flip[k] = if h > 0.0 { 1 } else { -1 };
                self.delta[k] = (h - r).abs();
                self.last_flip_s[k] = time_s;
                flipped += 1;
            }
            self.h_ref[k] = h;
        }
        self.group();
        FlipSummary {
            flipped_points: flipped,
        }
    }

    fn group(&mut self) {
        self.events.clear();
        self.event_tris.clear();
        for l in &mut self.label {
            *l = NONE;
        }
        let (nx, ny) = (self.nx, self.ny);
        for seed in 0..self.flip.len() {
            if self.flip[seed] == 0 || self.label[seed] != NONE {
                continue;
            }
            let dir = self.flip[seed];
            if self.events.len() == MAX_GRID_EVENTS {
                // Out of event slots: the rest joins the last event (never lost).
                let last = self.events.len() - 1;
                self.events[last].sum_delta += f64::from(self.delta[seed]);
                self.events[last].num_points += 1;
                self.label[seed] = last as u32;
                continue;
            }
            let id = self.events.len() as u32;
            let first_tri = self.event_tris.len() as u32;
            let mut ev = GridEvent {
                direction: dir,
                first_tri,
                ..Default::default()
            };
            self.stack.clear();
            self.stack.push(seed as u32);
            self.label[seed] = id;
            while let Some(k) = self.stack.pop() {
                let k = k as usize;
                ev.sum_delta += f64::from(self.delta[k]);
                ev.num_points += 1;
                let t = self.tri[k];
                if !self.event_tris[first_tri as usize..].contains(&t) {
                    self.event_tris.push(t);
                }
                let (i, j) = (k % nx, k / nx);
                let mut visit = |n: usize| {
                    if self.flip[n] == dir && self.label[n] == NONE {
                        self.label[n] = id;
                        self.stack.push(n as u32);
                    }
                };
                if i > 0 {
                    visit(k - 1);
                }
                if i + 1 < nx {
                    visit(k + 1);
                }
                if j > 0 {
                    visit(k - nx);
                }
                if j + 1 < ny {
                    visit(k + nx);
                }
            }
            ev.num_tris = self.event_tris.len() as u32 - first_tri;
            self.events.push(ev);
        }
    }

    /// Events of the last detection.
    pub fn num_events(&self) -> usize {
        self.events.len()
    }

    /// Event `k`.
    pub fn event(&self, k: usize) -> GridEvent {
        self.events[k]
    }

    /// The S_P triangles under event `k`'s grid points.
    pub fn event_triangles(&self, k: usize) -> &[u32] {
        let e = &self.events[k];
        &self.event_tris[e.first_tri as usize..(e.first_tri + e.num_tris) as usize]
    }
}
