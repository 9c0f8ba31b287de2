//! # The developable-geometry layer (steps (d)–(h) of the seeds' frame loop)
//!
//! After the physics step has moved S_P and S_G has read its positions (steps (a)–(c),
//! [`crate::sim`]), this layer runs the geometric analysis of the seeds (thesis §2.4–2.5,
//! `000_cb4d91e46ec5927f.txt`; TOG 2015 §4–6, `001_44bc28f7c5e9f81f.txt`; spec:
//! `../shared/notes/digest-crumpling.md` §3) and publishes what sound and tearing need
//! ([`GeometryFrame`], read through `Sim::geometry`). Per awake frame, in the Fig. 16 order
//! (digest §9 item 3: the documented Step 1 → 3 order, not Algorithm 1's):
//!
//! 1. **Dihedral angles and local shape** of every S_P edge and triangle: the signed hinge
//!    angle θ_e (the physics' own [`crate::physics::bending::dihedral`]) and, per triangle,
//!    the discrete shape operator in the pattern, S̄_t = Σ_e θ_e |ē| / (2Ā_t) · m̄_e m̄_eᵀ
//!    (m̄_e: in-plane unit normal of the pattern edge). Its large eigenvalue κ_t is the bending
//!    curvature; the eigenvector of the small one is the local **ruling direction** r̄_t; the
//!    bend across the triangle is β_t = |κ_t|·h_t (h_t: equilateral edge of the same area).
//!    An edge much sharper than the triangle's two others ([`CREASE_DOMINANCE`]) is a crease
//!    bounding a flat facet and is left out of that facet's shape operator, so a sharp fold
//!    between two flat parts is seen as the seeds see it: two flat regions and a crease.
//! 2. **Flat / curved classification with hysteresis** (§3.1, §3.6): a flat triangle turns
//!    curved when β_t > θ_high = θ0 = 0.01 rad, a curved one turns flat again only when
//!    β_t < θ_low = θ0/10 (P 792, T 965). Flat regions are the connected sets of flat triangles
//!    joined across edges with |θ_e| < θ0 (the seeds' coplanarity, P 537–542), so a flat region
//!    **splits** as soon as one of its edges bends beyond θ0 (T 813); an edge with |θ_e| ≥ θ0
//!    between two flat regions is a **crease**, the seeds' degenerate one-ruling curved region
//!    (T 740). Junction points are the boundary vertices where a flat and a curved triangle
//!    meet (P 303–306); the hysteresis keeps them from oscillating (P 792–794, digest test 8),
//!    and a curved region whose triangles all fall below θ_low becomes flat again (P 794–797).
//!    **Edge flips** (§3.1, T 811–828, the thesis' `flip_edges` before `treat_compression`):
//!    an interior S_P edge e1 between two flat triangles with |θ| < θ0 (so in one flat region)
//!    that is compressed, c_e = (l̄ − l)/l̄ > ε_c, while the other diagonal x1–x2 of its quad
//!    is not (3D length from the four vertices, rest length from the pattern), is flipped: the
//!    quad's triangles (u, w, x1), (w, u, x2) become (u, x2, x1), (w, x1, x2). On a lattice
//!    quad the other diagonal is perpendicular to e1, i.e. across the compression, where the
//!    sheet buckles (the ruling direction v⊥ of §3.2) and where the lattice has no hinge. The
//!    most compressed such edge of the frame is flipped by the sim at the start of the next
//!    step ([`GeometryLayer::take_pending_flip`], [`crate::sheet::refine::flip_edge`]: state
//!    carried over, masses re-lumped, `sim/remesh.rs`), one per frame, and reported as
//!    [`ShapeEvent::EdgeFlipped`]. Guards (impl. choice): the edge carries no rest angle or
//!    damage (a fold keeps its place), no vertex of the quad is held, next to a held vertex
//!    or singular, both new triangles keep angles ≥ 20° in the pattern (the lattice's flip
//!    gives 30°–30°–120°), the flip makes no crossing with another layer, and **the quad must
//!    bend across the other diagonal** (|θ(x1–x2)| ≥ θ_low and larger than |θ(e1)|; Fig. 2.5's
//!    lifted corner): a quad merely squeezed in its plane, as the whole sheet is at the onset
//!    of a crumple, keeps its triangles. Measured without that guard
//!    (`sim-core/examples/flip_probe.rs`): the first frames of C5 seed 7's squeeze flipped
//!    eight lattice edges into 30°–30°–120° pairs and a later frame strained a triangle by
//!    46 % (the scenario health limit is 10 %); with it, one flip or none per crumple run.
//! 3. **Compression analysis** (§3.2): the stretch tensor of every flat triangle
//!    ([`stretch`]); the most compressed one T_comp with c_t = 1 − λ_min > ε_c starts a pass.
//!    **Addition (impl. choice):** a *curved* triangle compressed along its own, well-defined
//!    ruling direction (|κ_small/κ_big| < [`ANISO_MAX`], compression direction within
//!    [`CONFLICT_RAD`] of the ruling) by more than `curved_eps_factor`·ε_c (40) also starts a
//!    pass, as a case A conflict in place (singular point about its most bent edge). The
//!    seeds never need this because their curved regions are developable by construction;
//!    on our fixed S_P a curved region compressed along its generators is exactly the
//!    situation that buckles into a d-cone (P 685–692). Triangles touching a held vertex do
//!    not start passes, nor do their neighbours (the hand's constraint strains them), and a singular vertex is never
//!    placed on or next to a held vertex (the pinch).
//! 4. **Imaginary-ruling propagation** (§3.3, Appendix A): from T_comp along ±v⊥ in the
//!    pattern ([`walk`]), through flat triangles of the same region, until a border: the sheet
//!    boundary (free border, case b), a crease (case c), or a curved region. A curved region
//!    whose own rulings are parallel to v⊥ (within [`CONFLICT_RAD`]) is simply extended; one
//!    whose rulings conflict continues the propagation through it to the first ruling bent
//!    beyond θ_sing (e_sing, case d, P 693–704). θ_sing is θ0 scaled by the ratio of the S_P
//!    edge to the seeds' ruling spacing 1/ρ_bound (the dihedral between two of our triangles
//!    spans that many of the seeds' rulings); a curved region counts as conflicting only if it
//!    is bent beyond θ_sing with a well-defined ruling direction (a weakly bent or twisted one
//!    simply grows). Border types: {∂S, ∂S} → a generalized cylinder
//!    (rulings ∥ v⊥, Fig. 7); {∂S, singular} → a cone through the new singular point
//!    (Fig. 8); {singular, singular} → degenerate (Fig. 9). The strip's triangles become curved
//!    (the new curved region). Up to [`GeometryConfig::max_passes`] passes per frame (digest
//!    §3.4 impl. choice); a triangle that started a pass waits [`REFRACTORY_FRAMES`].
//! 5. **Singular-vertex generation** (§3.5) at crease and conflicting-ruling borders: s̄ is
//!    drawn with the seeds' law about ē_sing ([`placement`], seeded RNG, σ from the material).
//!    Persistent: never removed, never moved in 2D.
//!    **Addition (impl. choice): non-developable vertices.** The seeds' physics leaves flat
//!    triangles compressed by ≈ 1 % (their physics-only c_mean 0.9–1.5 %), so compression
//!    analysis alone finds their d-cones. Our Newton step runs to convergence on a fine,
//!    fully bendable S_P (c_mean ≈ 0.01 %): squeezed, the lattice folds at its own edges
//!    instead of compressing, and the full crumple found no compressed flat triangle at all.
//!    What it does show is where ruling families meet: the Gauss image of a vertex's 1-ring
//!    (its triangles' unit normals) lies along one arc at a developable point (cylinder,
//!    cone, twist) and spreads in two directions where two bends cross. With φ the minor
//!    spread (√ of the small eigenvalue of the normals' covariance in their mean tangent
//!    plane), a smooth doubly curved cap of that extent would need a compression of about
//!    φ²/6 (chord ratio sin φ/φ); a vertex with φ²/6 > `gauss_eps_factor`·ε_c (15, calibrated
//!    on the seed scenarios: twist 0, double bend 1–4, full crumple ≥ 15 at the median over seeds) becomes singular
//!    (case [`SingularCase::NonDevelopable`]), most spread first, ≥ `gauss_min_spacing_m`
//!    (2 cm) from existing singular vertices. Being tied to ε_c, a thicker paper gets fewer
//!    points and the ε_c sweep of Fig. 21 stays monotone.
//! 6. **Fibre damage** (§2.3, P eq. 1, T eq. 2.1–2.2): around a new singular vertex i with
//!    N_i incident S_P edges, every incident edge gets rest angle += ±Θ_rest/N_i (Θ_rest = π/8)
//!    with the sign of its current fold (digest §9 item 8: interior vertices only, sign at
//!    creation) and damage += D/N_i (D = 10, k_b/(1 + d)): the physics then keeps the d-cone,
//!    so a crumpled sheet does not spring back flat, while a smoothly bent one does (P 489–491).
//! 7. **Region partition, rulings, free borders** (§5.1): curved regions grow from their most
//!    bent triangle over curved neighbours (by edge or vertex: a fold across the lattice's
//!    diagonals touches at vertices) whose region-scale ruling direction — the shape operator
//!    summed over the triangle and its edge neighbours — is within 45° of the seed's, so a
//!    region is one family of rulings (pairwise chaining let one region turn across a whole
//!    crumpled sheet). A flat triangle with no coplanar flat neighbour that touches a curved
//!    one is a facet of that curved region and turns curved (before: a fold across the
//!    lattice left a chain of one-triangle flat regions). Crease edges between the same two
//!    flat regions form one crease region (one ruling per S_P edge, dihedral = θ_e). Rulings
//!    are straight pattern lines traced along the region-scale r̄_t through the region
//!    (seeded at the most bent uncovered triangle, one strip of triangles per ruling) with
//!    2D/3D endpoints, length, tangent-plane normal and dihedral angle (the mean signed κ
//!    along the ruling × the ruling spacing, i.e. the angle between the tangent planes of
//!    neighbouring rulings, as the seeds' quads have).
//! 8. **Generalized-cone fitting** (§3.7, [`cone`]): per curved region, rulings ordered across
//!    it, least-squares apex on the Blaschke cylinder, segmentation into cones with
//!    ε_blaschke = 0.5 % L_paper, gap cones between segments; a region containing a singular
//!    vertex is one cone with that apex (T 977). Then **ruling realignment and boundary
//!    resampling** ([`realign`], §3.7 steps 1–7): every ruling of a fitted cone is turned
//!    about its anchor through the cone's pattern apex ā_proj (parallel to the axis for a
//!    cylinder) and traced again on S_P, and rulings are inserted where neighbouring border
//!    ends are more than 1/ρ_bound apart, so S_G's rulings are those of its cones.
//! 9. **Isometry** (§3.8, [`isometry`]): Phase I (edge directions, two Lagrange multipliers,
//!    2×2 solves) and Phase II (positions, least squares, held vertices fixed), then no vertex
//!    is let deeper into an obstacle than it was; a facet turned by more than 0.3 rad, or
//!    turned over from its normal at the frame's start, or a correction that carries the
//!    sheet through itself (it knows nothing of sheet–sheet contact), discards it, and frames
//!    with a vertex faster than `IsometryConfig::max_speed_m_s` skip it (measured: in hostile stress runs the
//!    position-only correction during violent motion let later physics steps turn facets
//!    over); a still sheet skips it unless an edge is compressed by more than 1 % (isometry.rs
//!    "When it runs"). Targets are compression-only by default
//!    (stretched edges keep their length; measured: the symmetric targets raised c_mean above
//!    the physics alone, see `docs/benchmarks.md`).
//! 10. **Sudden shape changes** ("clac", T 1247, 1261): new singular vertices, new curved
//!     regions, flattened triangles, flat-region splits, junction moves and the largest vertex
//!     jump of the frame are listed in [`GeometryFrame::events`] (never smoothed).
//! 11. **Coarsening** (the seeds' "coarse flat triangles" of S_P regeneration, P 351–354,
//!     T 734–744; digest §2.2; plan step 2 of `docs/sp-regeneration-plan.md`): every
//!     [`COARSEN_PERIOD_FRAMES`] frames, the last S_P vertex beyond the initial lattice that
//!     is not singular — in practice a vertex a strip cut added (below) — is taken out again
//!     when the sheet has opened out flat and still around it: its triangles are all flat,
//!     its edges uncreased and bent by less than θ0, it is neither held nor next to a held
//!     vertex, it moves with its neighbours (relative speed < [`COARSEN_MAX_REL_SPEED_M_S`]),
//!     and a neighbour can take its place with well-shaped triangles. The sim collapses it
//!     into that neighbour at the start of the next step ([`crate::sheet::coarsen`]: edge
//!     collapse, Delaunay flips, state carried over, the vertices after it one index lower;
//!     `sim/remesh.rs`), one per step and only when no other mesh change is pending, and
//!     reports [`ShapeEvent::VertexCollapsed`]. The lattice's vertices and singular vertices
//!     are never taken out, so the mesh never becomes coarser than the lattice, and with
//!     strip cutting off (the default) nothing is ever taken out. A sleeping sheet does no
//!     work, so a cut vertex left when it falls asleep goes once it is woken. Measured
//!     (`sim-core/examples/coarsen_probe.rs`): a sheet held at both short edges, arched and let
//!     go (the test script of `sim/remesh.rs`) gets 2 cuts with 4 new vertices in its first
//!     0.1 s, and all 4 go between frames 301 and 370, as the arch flattens out (one per
//!     [`COARSEN_PERIOD_FRAMES`]); in the slide S1 one of the 15 its 2 cuts added goes, the
//!     others lie on the hinge the sheet stays bent along (|θ| ≈ 0.03 rad at rest).
//!
//! ## Simplifications against the seeds (said plainly)
//!
//! - **S_P keeps its connectivity, except at singular points and flipped edges.** The seeds regenerate S_P from
//!   S_G every frame (coarse flat triangles + Delaunay enrichment, quads with barycentre
//!   vertices along rulings, §2.2). Here S_G's regions, rulings and cones are computed *on*
//!   S_P (a region is a set of S_P triangles; a ruling is a traced pattern line), and S_P
//!   changes only where S_G gains a vertex: a singular point gets an S_P vertex at its drawn
//!   position (next bullet), inserted with state transfer ([`crate::sheet::refine`]), and
//!   where a compressed flat edge is flipped (step 2). By default strip
//!   cutting marks the strip's triangles curved instead of inserting rulings (the opt-in cut
//!   is the next bullet but one); cone
//!   **realignment and boundary resampling** (§3.7 steps 1–7) act on S_G's published rulings
//!   only ([`realign`]: the physics does not see them). Reasons: the physics solver's sparse
//!   factorization, the allocation-free step, the plugin's preallocated mesh and per-vertex
//!   contacts all stay valid between singular points (an insertion rebuilds them, an event
//!   like a reset); and our physics on the lattice already measures c_mean ≈ 0.01–0.03 %,
//!   well inside the seeds' post-remeshing figures. Measured since: adopting a changed S_P
//!   (`Sim::adopt_mesh`: physics with its symbolic factorization, layer, rig) costs 1.2 ms, more
//!   than the whole frame budget, so a regeneration must be an event, not a per-frame step;
//!   the plan for strip cutting and regeneration is `docs/sp-regeneration-plan.md`. The
//!   seeds' per-frame regeneration is built as an opt-in mode
//!   ([`GeometryConfig::regenerate_sp`], [`crate::sheet::regenerate`]: S_P rebuilt from S_G
//!   after steps (d)–(f), then the isometry step on the new S_P) and measured against this
//!   default over every seed scene (`sim-core/examples/regen_probe.rs`): 3.7–8.9× the frame
//!   time, c_mean 0.06–0.67 % against 0.0004–0.028 %, and singular points where the default
//!   has none (the twist C2: 25) — the chords new vertices are interpolated on compress the
//!   sheet each frame, and the compression analysis reads that as buckling. Figures and
//!   reasons in the plan.
//! - **A singular point gets an S_P vertex at s̄.** s̄ is sampled with the seeds' law and σ
//!   ([`SingularPoint::sampled2`]) about ē_sing. The eligible S_P vertex nearest to it among
//!   the two faces of ē_sing (interior, not held, not yet singular) moves there in the
//!   pattern if the triangles around it stay well shaped
//!   ([`crate::sheet::physical::PhysMesh::move_pattern_vertex`]: rest data and masses follow,
//!   the 3D point is lifted onto the current surface); otherwise the point waits
//!   ([`PendingSingular`]) and after the frame the sim inserts a new S_P vertex at s̄
//!   ([`crate::sheet::refine`], `sim/remesh.rs`): edge or triangle split, Delaunay flips of
//!   unbent, undamaged edges, the new vertex placed on the surface where its edges have their
//!   pattern lengths, state carried over), which then becomes the singular vertex. Where s̄
//!   falls next to an existing vertex or the split would make thin triangles, the vertex goes
//!   to the nearest accepted point (≤ half-way to its triangle's centre); where even that is
//!   refused, the nearest vertex moves part of the way as before. Where s̄ lies just off a
//!   sharply folded S_P edge, the vertex goes to the foot of s̄ on that edge, so that no new
//!   triangle spans the fold (`sheet/refine.rs`, step 2): the law's offset across the edge is
//!   dropped there (an approximation; the seeds' S_P, rebuilt around s̄, has no such edge).
//!   **On by default** ([`GeometryConfig::insert_singular_vertices`]; off: the nearest vertex
//!   moves part of the way everywhere and S_P's connectivity never changes). It was opt-in
//!   while insertion stopped the full crumple early (C5 seed 1: 3 singular points, squeeze
//!   0.43). The cause was not the mesh: parry3d's GJK on two triangles, in metres, reported
//!   two layers 7 mm apart as crossing (its tolerances are absolute), the pass-through guard
//!   undid the frame and the crumple limit held. With exact distances
//!   ([`crate::triangle_distance`]) one real defect remained: the new vertex, relaxed onto its
//!   pattern lengths, could cross a layer of a fold 1.4 mm away, and every later frame was
//!   undone from that crossed start (C5 seed 2: 461 undone frames); the relaxation now
//!   refuses such steps and an insertion that makes the sheet cross itself is refused
//!   (`sim/remesh.rs`). Measured with `sim-core/examples/insert_probe.rs` (C5 seeds 1–8,
//!   insertion on / off, crumple stop at 1 mm, edge flips on): 26/22, 26/33, 28/29, 35/22,
//!   21/26, 30/23, 27/23, 39/30 singular points, 9–23 per run exactly at s̄ (off: 1–6), 17–30
//!   vertices inserted; S4 23/22; 0–2 undone frames per run in either mode; c_mean
//!   0.007–0.047 % either way and the same largest strain; time per frame 0.9–1.7× (the mesh
//!   grows; the two modes squeeze to different depths). Before edge flips: 30/29, 38/31,
//!   28/29, 28/25, 32/30, 30/23, 19/23, 39/30; S4 45/31. With the stop at 4 mm (until 2026-11-26):
//!   26/24, 30/20, 22/17, 25/19, 23/20, 23/17, 17/13, 27/22. The twist, the double bend and the other scenes
//!   place the same singular points either way.
//!   When no vertex is eligible nothing is created (the seeds' rare failure, P 1631).
//! - **Strip cutting is built but off by default** ([`GeometryConfig::cut_strips`]). The
//!   seeds cut the flat region along a new strip's extremal rulings and remesh the strip as a
//!   curved region whose rulings are edges (P 459–487, T 879–906). Our strip is the one line
//!   of triangles the propagation walk crossed, so the cut is along that walk's line, the
//!   imaginary ruling itself: every S_P edge it crossed, up to and including its border edge,
//!   is split where the line crosses it, or the line snaps to the edge's end when the crossing
//!   is within a third of the edge from it, then Delaunay flips about the new vertices
//!   ([`crate::sheet::cut`]). The ruling becomes a chain of S_P edges, a straight hinge the
//!   sheet can bend along; the shape and the energy do not change (each new vertex lies on an
//!   old straight edge). One cut per frame (the frame's first new strip), done by the sim at
//!   the start of the next step like a vertex insertion (`sim/remesh.rs`, announced by
//!   `Sim::refinement_pending`, saved with the sheet). A line through a hand's pinch is not
//!   cut, nor a strip of fewer than [`MIN_CUT_STRIP_TRIANGLES`]. Measured
//!   (`sim-core/examples/insert_probe.rs` with `CUT=1`, C5 seeds 1–8): cutting through the
//!   pinch and snapping only within a fifth of the edge made 4–10 cuts per run, short edges
//!   next to the held corners and a largest strain of 0.19 and 0.27 in two seeds (health
//!   limit 0.1). As built, cuts happen only at a gesture's onset (frames 9–21, the first
//!   compression passes): 0–2 per run; 23–35 singular points (median 27; without cuts 26,
//!   23, 28, 29, 31, 25, 27, 35, median 27.5), largest strain ≤ 0.074 (without cuts one
//!   frame of seed 4 reaches 0.18, about an inserted vertex), c_mean 0.010–0.043 % (measured
//!   2026-11-27 after the contact coupling of `physics/sparse.rs` moved to the split factor).
//!   The other scenes
//!   keep their targets: the twist has no singular point and its largest strain falls from
//!   0.045 to 0.006 (c_mean 0.015 → 0.007 %); the double bend C4 makes 2 in each of seeds 2–6
//!   and its own (1–5 without cuts). Why it stays opt-in: every cut only adds triangles (S1
//!   130 → 158) and frame time while the sheet stays bent along them (coarsening, step 11,
//!   takes a cut's vertices out only where the sheet has opened out flat again). Robustness
//!   no longer keeps it off: `sim-stress --frames 10000 --seed S --sessions 1 --cut-strips`
//!   passes for S = 1–24 (2026-11-27, with coarsening; largest strain 0.31–0.94; 13–45 cuts
//!   per session, 0–12 vertices taken out again), as the default does.
//! - **Edge flips act on S_P** (step 2 above, digest test 2): the seeds flip edges of the
//!   coarse S_G triangulation of a flat region so that a fold across its other diagonal can
//!   be seen (their S_P, resampled from S_G, bends underneath). Here S_G's flat regions are
//!   S_P triangles, so the flip changes the physical mesh: it gives the sheet a hinge across
//!   the compression. A lattice flip makes a 30°–30°–120° pair with a √3-times longer edge,
//!   so flips are guarded (above) and rare: one or none per crumple run, none in the other
//!   seed scenes. Once an S_P edge folds beyond θ0 the region splits along it as the seeds'
//!   does after their flip. `GeometryConfig::flip_compressed_edges = false` turns flips off.
//! - **Curvature analysis on the fine mesh** replaces the seeds' per-region ruling bookkeeping:
//!   region classification uses the discrete shape operator with the seeds' thresholds.
//!
//! ## Digest §9 discrepancies, resolved
//!
//! | # | resolution here |
//! |---|---|
//! | 1 σ | 0.1 cm for printer and banknote, 0.05 cm for tracing ([`crate::material`]); `GeometryConfig::sigma_m` overrides |
//! | 2 ρ | ρ_bound = 1.2/cm bounds the ruling spacing from below; S_P density is [`crate::sheet::MeshConfig`] (≈ 130–190 triangles) |
//! | 3 order | Fig. 16 order (analysis → junctions/classification → cones → isometry); classification runs first since it also decides which triangles are analysed |
//! | 4 t_iso | per-frame budget = Table V: Phase I is capped at `IsometryConfig::phase1_max_iters` (40, stops early), not run to convergence |
//! | 5 N_s | the target is ≥ 15 for the full crumple: 23–35 per seed over seeds 1–8 (median 27.5; without vertex insertion 22–29), the crumple cap stopping the squeeze where the sheet would pass through itself, at a chaotic point (`tests/geometry.rs`) |
//! | 6 ε_blaschke | RMS distance √(e/N) compared with 0.5 % L_paper |
//! | 7 λ | c_t = 1 − λ_min |
//! | 8 fibre damage | interior singular vertices only, sign of the fold at creation, D = 10 applied |
//! | 9 tangent control | handled by [`crate::handles`] (2 neighbours at a corner, 3 on a border, 4 inside: the seeds give 2 on a border and up to 4 at a corner, digest §9 item 9; ours hold a corner by its two edges and keep a border grip from rotating about the edge line) |
//! | 10 span removed around a new singularity | no rulings are stored per triangle, so nothing is removed: the new apex's fan is what the region partition and cone fit see next frame |
//! | 11 W_stress | standard StVK ([`crate::physics::membrane`]) |
//! | 12 a_max | ridges are rulings with dihedral > [`RIDGE_RAD`] = 0.5 rad |
//! | 13 Algorithm 3 | closed-interval segmentation ([`cone::segment`]) |
//!
//! ## Where each step lives
//!
//! This file holds the layer's state, its frame loop ([`GeometryLayer::update`]) and the tests
//! that play several steps together; each step is a child module implementing its part of
//! [`GeometryLayer`]:
//!
//! | step | module |
//! |---|---|
//! | 1–2 shape, classification | `shape` (and `flip`, the compressed-edge flip) |
//! | 3–4 compression, propagation, strips | `compression` ([`stretch`], [`walk`]) |
//! | 5 singular vertices, 6 fibre damage | `singular` ([`placement`]), `nondevelopable` |
//! | 7 partition, rulings | `partition`, `rulings` |
//! | 8 cones, realignment, resampling | `region_cones` ([`cone`]), [`realign`] |
//! | 9 isometry | `isometry_step` ([`isometry`]) |
//! | 10 published outputs and events | `frame` ([`GeometryFrame`], [`ShapeEvent`]) |
//! | 11 coarsening | `coarsening` |
//! | settings, saved state, mesh changes | `config`, `saved`, `remesh` |
//!
//! ## Allocation and determinism
//!
//! Every buffer is sized in [`GeometryLayer::new`] from S_P (whose connectivity changes only
//! when a vertex is inserted or an edge flipped, and then [`GeometryLayer::remeshed`] builds
//! a new layer);
//! `update` only writes into them (sorts are in-place `sort_unstable_by` with index
//! tie-breaks). The only randomness is the layer's own `Pcg32`, seeded from the sheet's seed
//! and saved with the sheet.

mod coarsening;
mod compression;
pub mod cone;
mod config;
mod flip;
mod frame;
pub mod isometry;
mod isometry_step;
mod nondevelopable;
mod partition;
pub mod placement;
pub mod realign;
mod region_cones;
mod remesh;
mod rulings;
mod saved;
mod shape;
mod singular;
pub mod stretch;
pub mod walk;

use rand::SeedableRng;

use crate::collision::{CONTACT_SKIN_M, Obstacles};
use crate::material::PaperMaterial;
use crate::math::{V2, V3, sym2_eigen};
use crate::physics::bending::dihedral;
use crate::self_proximity::SelfProximity;
use crate::sheet::cut::EdgeCrossing;
use crate::sheet::geometric::{GVertex, GeomStructure, VKind};
use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;
use cone::{RulingPlane, apex_in_pattern, gap_apex, segment};
use isometry::{Isometry, IsometryConfig, IsometryReport};

pub use config::GeometryConfig;
pub use frame::{
    ConeInfo, FreeBorderEdge, GeometryFrame, PendingFlip, PendingSingular, Region, RegionKind,
    RulingInfo, ShapeEvent, SingularCase, SingularPoint, TriKind,
};
pub use saved::SavedGeometry;

/// Coplanarity threshold θ0 (P 1515–1519, Table VI), radians.
pub const THETA0_RAD: f64 = 0.01;
/// Junction hysteresis: a curved triangle turns flat below θ_low = θ0/10 (P 792).
pub const THETA_LOW_RAD: f64 = THETA0_RAD / 10.0;
/// Junction hysteresis: a flat triangle turns curved above θ_high = θ0 (P 792).
pub const THETA_HIGH_RAD: f64 = THETA0_RAD;
/// Plastic rest-angle budget per singular vertex Θ_rest = π/8 (P 510–518, T 775).
pub const THETA_REST_RAD: f64 = std::f64::consts::PI / 8.0;
/// Bending damage per singular vertex D = 10 (T 767–775).
pub const DAMAGE_D: f64 = 10.0;
/// Boundary sampling density ρ_bound = 1.2 per cm (Table VI), per metre.
pub const RHO_BOUND_PER_M: f64 = 120.0;
/// ε_blaschke as a fraction of L_paper (0.5 %, Table VI).
pub const EPS_BLASCHKE_FRAC: f64 = 0.005;
/// Ridge threshold a_max of the sound model (digest §9 item 12), radians.
pub const RIDGE_RAD: f64 = 0.5;
/// Largest angle between v⊥ and a curved region's rulings for the propagation to merge into
/// it instead of conflicting (impl. choice), radians.
pub const CONFLICT_RAD: f64 = 0.35;
/// A triangle's ruling direction is well defined when its small principal curvature is
/// below this fraction of the large one (|κ_small/κ_big|; a twisted, saddle-like triangle has
/// ≈ 1 and has no ruling to conflict with).
pub const ANISO_MAX: f64 = 0.3;
/// An edge whose |θ| exceeds this × the sum of the triangle's two other |θ| (plus θ0) is a
/// crease bounding a flat facet, not part of the facet's curvature (impl. choice).
pub const CREASE_DOMINANCE: f64 = 4.0;
/// Frames a triangle that started a propagation pass waits before starting another.
pub const REFRACTORY_FRAMES: u64 = 20;
/// Cosine of the largest facet rotation the isometry step may make in one frame (0.3 rad).
pub const ISO_MAX_TURN_COS: f64 = 0.955_336_489_125_606;
/// Undriven, the isometry step runs again only when the largest edge compression exceeds the
/// one it last met by this factor (see the isometry step, module doc step 9).
pub const ISO_REBUILT_FACTOR: f64 = 1.1;
/// A vertex jump above this is reported as an event, metres.
pub const JUMP_EVENT_M: f64 = 5e-4;
/// Capacity of the per-frame event list.
pub const MAX_EVENTS: usize = 64;
/// Longest propagation walk, in triangles.
const MAX_WALK: usize = 256;
/// A strip of fewer triangles is not cut (`GeometryConfig::cut_strips`): its borders are a
/// triangle or two apart, so its cut would split an edge or two, a vertex more and no
/// straight hinge (the double bend C4 and the crumples make many one- and two-triangle
/// strips once their sheet is folded).
pub const MIN_CUT_STRIP_TRIANGLES: usize = 4;
/// Most edge crossings of a strip's cut line (both walks).
const MAX_CUT_CROSSINGS: usize = 2 * MAX_WALK + 2;

/// The layer looks for a vertex to take out of a flat region ([`GeometryConfig::coarsen_flat_regions`])
/// once every this many frames (20: 0.1 s at 200 frames/s): a cut's few vertices go within a
/// second of the sheet opening out, and a collapse the sim refuses is not retried every frame.
pub const COARSEN_PERIOD_FRAMES: u64 = 20;
/// A vertex is taken out only while it moves with its neighbours: no relative speed above
/// this, m/s (its own momentum goes with it, [`crate::sheet::coarsen`]).
pub const COARSEN_MAX_REL_SPEED_M_S: f64 = 0.01;

/// Where a propagation direction ended.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Border {
    /// Sheet boundary: a free border.
    Free,
    /// A curved region with compatible rulings (it grows).
    Compatible,
    /// A crease edge (case B).
    Crease(u32),
    /// A bent ruling inside a conflicting curved region (case A).
    InCurved(u32),
    /// The walk failed (degenerate) or ran too long.
    None,
}

/// Whether a partition may turn lone flat facets beside curved triangles curved
/// ([`GeometryLayer::restore`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Promote {
    Yes,
    No,
}

/// The geometry layer: persistent state and preallocated workspace.
#[derive(Clone, Debug)]
pub struct GeometryLayer {
    cfg: GeometryConfig,
    eps_c: f64,
    sigma_m: f64,
    l_paper_m: f64,
    spacing_m: f64,
    theta_sing: f64,
    out: GeometryFrame,
    curved: Vec<bool>,
    prev_curved: Vec<bool>,
    refractory_until: Vec<u64>,
    is_singular: Vec<bool>,
    near_held: Vec<bool>,
    tri_kappa: Vec<f64>,
    tri_aniso: Vec<f64>,
    tri_ruling: Vec<V2>,
    tri_shape: Vec<[f64; 3]>,
    grow_order: Vec<u32>,
    crease_edges: Vec<(u32, u32, u32)>,
    grow_stack: Vec<u32>,
    grown: Vec<bool>,
    tri_ruling_smooth: Vec<V2>,
    tri_bend: Vec<f64>,
    tri_normal: Vec<V3>,
    tri_h: Vec<f64>,
    vert_tris_start: Vec<u32>,
    vert_tris: Vec<u32>,
    vert_spread2: Vec<f64>,
    uf: Vec<u32>,
    root_region: Vec<u32>,
    order: Vec<u32>,
    /// Per region, where its curved triangles end in `order` (the trace's buckets); one more
    /// than the regions' capacity.
    region_end: Vec<u32>,
    covered: Vec<bool>,
    ruling_tris: Vec<u32>,
    strip: Vec<u32>,
    vflat: Vec<bool>,
    vcurved: Vec<bool>,
    junction_prev: Vec<bool>,
    planes: Vec<RulingPlane>,
    ruling_next: Vec<RulingInfo>,
    ruling_map: Vec<u32>,
    pos_before: Vec<V3>,
    /// Crossing test of the isometry's correction.
    proximity: SelfProximity,
    iso: Isometry,
    rng: rand_pcg::Pcg32,
    iso_undriven_compression: f64,
    frames_processed: u64,
    /// A singular vertex waiting for its inserted S_P vertex (at most one per frame).
    pending: Option<PendingSingular>,
    /// An edge waiting to be flipped (at most one per frame).
    pending_flip: Option<PendingFlip>,
    /// The crossings of the last propagation's strip, in line order (workspace).
    cut_line: Vec<EdgeCrossing>,
    /// A strip waiting to be cut along `pending_cut` (at most one per frame): frame found.
    pending_cut_frame: Option<u64>,
    /// Its crossings, in line order.
    pending_cut: Vec<EdgeCrossing>,
    /// Vertices below this index are the initial lattice's (never taken out).
    coarsen_from: usize,
    /// A vertex waiting to be taken out of a flat region: (vertex, frame found).
    pending_coarsen: Option<(u32, u64)>,
    /// This frame's event list was started before the layer ran ([`Self::start_events_early`]).
    keep_events: bool,
    /// The isometry step's crossing test found S_P's final positions of this frame crossing
    /// nowhere ([`Self::checked_uncrossed`]).
    checked_uncrossed: bool,
}

fn find(uf: &mut [u32], mut x: u32) -> u32 {
    while uf[x as usize] != x {
        let p = uf[uf[x as usize] as usize];
        uf[x as usize] = p;
        x = p;
    }
    x
}

fn union(uf: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(uf, a), find(uf, b));
    if ra != rb {
        // Lower index wins: deterministic roots.
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        uf[hi as usize] = lo;
    }
}

/// Seed of the layer's generator, derived from the sheet's seed (a separate stream from the
/// gesture rig's).
fn layer_seed(seed: u64) -> u64 {
    seed ^ 0x9e37_79b9_7f4a_7c15
}

impl GeometryLayer {
    /// A layer for `sp` (a new, flat sheet: every triangle flat, no singular vertex).
    pub fn new(sp: &PhysMesh, cfg: GeometryConfig, mat: &PaperMaterial, seed: u64) -> Self {
        let mut s = Self::unpublished(sp, cfg, mat, seed);
        s.refresh(sp, Promote::Yes);
        s
    }

    /// [`Self::new`] without publishing the current shape: for a layer whose state is
    /// restored next ([`Self::restore`] publishes it then).
    fn unpublished(sp: &PhysMesh, cfg: GeometryConfig, mat: &PaperMaterial, seed: u64) -> Self {
        let cfg = cfg.sanitized();
        let (nv, nt, ne) = (sp.num_vertices(), sp.num_triangles(), sp.num_edges());
        let (mut lo, mut hi) = (V2::repeat(f64::MAX), V2::repeat(f64::MIN));
        for q in &sp.pattern {
            lo = lo.inf(q);
            hi = hi.sup(q);
        }
        let ext = hi - lo;
        let spacing_m = sp.edge_rest_len_m.iter().sum::<f64>() / ne.max(1) as f64;
        let nreg = nt + ne;
        let out = GeometryFrame {
            tri_region: vec![0; nt],
            tri_kind: vec![TriKind::Flat; nt],
            regions: Vec::with_capacity(nreg),
            rulings: Vec::with_capacity(nreg),
            free_borders: Vec::with_capacity(ne),
            singular: Vec::with_capacity(nv),
            cones: Vec::with_capacity(2 * nreg),
            junctions: Vec::with_capacity(nv),
            held: Vec::with_capacity(nv),
            edge_dihedral_rad: vec![0.0; ne],
            events: Vec::with_capacity(MAX_EVENTS),
            ..GeometryFrame::default()
        };
        let mut s = Self {
            cfg,
            eps_c: 0.0,
            sigma_m: 0.0,
            l_paper_m: ext.x.max(ext.y).max(1e-6),
            spacing_m,
            theta_sing: THETA0_RAD * (spacing_m * RHO_BOUND_PER_M).max(1.0),
            out,
            curved: vec![false; nt],
            prev_curved: vec![false; nt],
            refractory_until: vec![0; nt],
            is_singular: vec![false; nv],
            near_held: vec![false; nv],
            tri_kappa: vec![0.0; nt],
            tri_aniso: vec![1.0; nt],
            tri_ruling: vec![V2::x(); nt],
            tri_shape: vec![[0.0; 3]; nt],
            grow_order: Vec::with_capacity(nt),
            crease_edges: Vec::with_capacity(ne),
            grow_stack: Vec::with_capacity(nt),
            grown: vec![false; nt],
            tri_ruling_smooth: vec![V2::x(); nt],
            tri_bend: vec![0.0; nt],
            tri_normal: vec![V3::z(); nt],
            tri_h: sp
                .tri_rest
                .iter()
                .map(|r| (4.0 * r.area_m2 / 3f64.sqrt()).sqrt())
                .collect(),
            vert_tris_start: Vec::new(),
            vert_tris: Vec::new(),
            vert_spread2: vec![0.0; nv],
            uf: (0..nt as u32).collect(),
            root_region: vec![NONE; nt],
            order: Vec::with_capacity(nt),
            region_end: Vec::with_capacity(nt + ne + 1),
            covered: vec![false; nt],
            ruling_tris: Vec::with_capacity(2 * MAX_WALK + 2),
            strip: Vec::with_capacity(2 * MAX_WALK + 2),
            vflat: vec![false; nv],
            vcurved: vec![false; nv],
            junction_prev: vec![false; nv],
            planes: Vec::with_capacity(nreg),
            ruling_next: Vec::with_capacity(nreg),
            ruling_map: Vec::with_capacity(nreg),
            pos_before: vec![V3::zeros(); nv],
            proximity: SelfProximity::with_capacity(sp.num_triangles()),
            iso: Isometry::new(sp),
            rng: rand_pcg::Pcg32::seed_from_u64(layer_seed(seed)),
            iso_undriven_compression: 0.0,
            checked_uncrossed: false,
            frames_processed: 0,
            pending: None,
            pending_flip: None,
            cut_line: Vec::with_capacity(MAX_CUT_CROSSINGS),
            pending_cut_frame: None,
            pending_cut: Vec::with_capacity(MAX_CUT_CROSSINGS),
            coarsen_from: nv,
            pending_coarsen: None,
            keep_events: false,
        };
        let mut count = vec![0u32; nv + 1];
        for tri in &sp.triangles {
            for &v in tri {
                count[v as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            count[v + 1] += count[v];
        }
        let mut fill = count.clone();
        s.vert_tris = vec![0; 3 * nt];
        for (t, tri) in sp.triangles.iter().enumerate() {
            for &v in tri {
                s.vert_tris[fill[v as usize] as usize] = t as u32;
                fill[v as usize] += 1;
            }
        }
        s.vert_tris_start = count;
        s.set_material(mat);
        for &v in &sp.singular {
            s.is_singular[v as usize] = true;
        }
        s
    }

    /// Publishes the partition, rulings and cones of the current shape without changing
    /// anything (a new or restored sheet, before its first awake frame).
    fn refresh(&mut self, sp: &PhysMesh, promote: Promote) {
        self.analyse_shape(sp);
        self.partition(sp, promote);
        self.trace_rulings(sp);
        self.fit_cones();
        self.realign_rulings(sp);
        self.out.events.clear();
        self.out.junction_moves = 0;
    }

    /// Applies a material's ε_c and σ (unless overridden by the configuration).
    pub fn set_material(&mut self, mat: &PaperMaterial) {
        self.eps_c = self.cfg.eps_c.unwrap_or(mat.eps_c);
        self.sigma_m = self.cfg.sigma_m.unwrap_or(mat.sigma_m);
    }

    /// The configuration.
    pub fn config(&self) -> &GeometryConfig {
        &self.cfg
    }

    /// Compression limit ε_c in use.
    pub fn eps_c(&self) -> f64 {
        self.eps_c
    }

    /// Placement spread σ in use, metres.
    pub fn sigma_m(&self) -> f64 {
        self.sigma_m
    }

    /// The outputs of the last processed frame.
    pub fn frame(&self) -> &GeometryFrame {
        &self.out
    }

    /// Work counter: frames the layer processed (does not move while the sheet sleeps).
    pub fn frames_processed(&self) -> u64 {
        self.frames_processed
    }

    /// Clears the per-frame event list (a frame in which the layer did not run).
    pub fn idle_frame(&mut self, frame: u64) {
        self.out.frame = frame;
        self.checked_uncrossed = false;
        if !std::mem::take(&mut self.keep_events) {
            self.out.events.clear();
            self.out.events_dropped = 0;
        }
        self.out.max_vertex_jump_m = 0.0;
        self.out.junction_moves = 0;
    }

    /// True if this frame's isometry step tested S_P's positions as it left them and found no
    /// two vertex-disjoint triangles crossing (the test of
    /// [`crate::self_proximity::SelfProximity::any_crossing`]). The sim's pass-through guard
    /// then has nothing to find and skips its own sweep of the same positions (`Sim::step`);
    /// false when the step did not run, was reverted before its test, or left a crossing.
    pub fn checked_uncrossed(&self) -> bool {
        self.checked_uncrossed
    }

    /// Re-reads the singular points' 3D positions from S_P, after the sim moved S_P once the
    /// layer had run (the pass-through guard undoing a frame, `Sim::step`).
    pub fn sync_positions(&mut self, sp: &PhysMesh) {
        for s in &mut self.out.singular {
            s.pos3 = sp.pos[s.sp_vertex as usize];
        }
    }

    /// Runs steps (d)–(h) on an awake frame. `fixed`: vertices held this frame (kept in place
    /// by the isometry step). `driven`: a hand or an obstacle moved the sheet this frame (the
    /// isometry step's trigger, [`IsometryConfig::trigger_compression`]). `start_normals`:
    /// the triangles' unit normals at the start of the frame, from which the physics never
    /// turns a triangle over, and neither may the isometry step (empty: no such reference).
    #[allow(clippy::too_many_arguments)] // the frame loop's state, passed explicitly
    pub fn update(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        fixed: &[bool],
        obstacles: &Obstacles,
        frame: u64,
        driven: bool,
        start_normals: &[V3],
    ) {
        self.frames_processed += 1;
        self.out.frame = frame;
        if !std::mem::take(&mut self.keep_events) {
            self.out.events.clear();
            self.out.events_dropped = 0;
        }
        self.out.held.clear();
        self.out
            .held
            .extend((0..fixed.len() as u32).filter(|&v| fixed[v as usize]));
        self.analyse_shape(sp);
        self.classify();
        self.mark_near_held(sp, fixed);
        if self.cfg.flip_compressed_edges {
            self.find_flip(sp, frame);
        }
        let flats_before = self.out.num_flat_regions;
        let made = self.treat_compression(sp, sg, fixed, frame);
        if self.cfg.gauss_eps_factor.is_finite() {
            self.treat_nondevelopable(sp, sg, fixed, frame, made);
        }
        self.partition(sp, Promote::Yes);
        if flats_before > 0 && self.out.num_flat_regions > flats_before {
            let after = self.out.num_flat_regions;
            self.out.push_event(ShapeEvent::FlatRegionSplit {
                before: flats_before,
                after,
            });
        }
        self.trace_rulings(sp);
        self.fit_cones();
        self.realign_rulings(sp);
        if self.cfg.regenerate_sp {
            // Step (h) runs on the regenerated S_P ([`Self::isometry_after_regeneration`]).
            self.checked_uncrossed = false;
        } else {
            self.isometry(sp, fixed, obstacles, driven, start_normals);
        }
        self.sync_positions(sp);
        if self.cfg.coarsen_flat_regions && frame.is_multiple_of(COARSEN_PERIOD_FRAMES) {
            self.find_coarsening(sp, frame);
        }
    }

    /// Starts this frame's event list before the layer runs (the sim places a pending singular
    /// vertex at the start of its step): the list is cleared now and kept when the layer runs.
    pub fn start_events_early(&mut self) {
        if !self.keep_events {
            self.out.events.clear();
            self.out.events_dropped = 0;
        }
        self.keep_events = true;
    }
}

/// A tiny sideways offset of a walk's start so that a line from a lattice triangle's
/// centroid does not run exactly through a vertex (an equilateral lattice has vertices right
/// above its centroids).
fn off_line(d: V2, h: f64) -> V2 {
    V2::new(-d.y, d.x) * (1e-3 * h)
}

/// Makes S_G's interior singular vertices match `sp.singular` (in order).
pub fn sync_sg_singular(sg: &mut GeomStructure, sp: &PhysMesh) {
    sg.vertices.retain(|v| v.kind != VKind::InteriorSingular);
    for &v in &sp.singular {
        sg.vertices.push(GVertex::interior_singular(sp, v));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Obstacles;
    use crate::room::RoomConfig;
    use crate::sheet::pattern::lattice;

    fn sheet() -> (PhysMesh, GeomStructure) {
        let sp = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.011), 0.0, 0.1).unwrap();
        let sg = GeomStructure::initial(&sp);
        (sp, sg)
    }

    /// A layer on its own (no sim): a singular point goes to the nearest vertex, moved towards
    /// s̄ (inserting a vertex at s̄ is the sim's part, tested in `sim/remesh.rs`).
    fn layer(sp: &PhysMesh) -> GeometryLayer {
        let cfg = GeometryConfig {
            isometry: IsometryConfig {
                enabled: false,
                ..IsometryConfig::default()
            },
            insert_singular_vertices: false,
            ..GeometryConfig::default()
        };
        GeometryLayer::new(
            sp,
            cfg,
            &PaperMaterial::of(crate::control::Material::Printer),
            1,
        )
    }

    /// The layer's frame for the test sheet placed on `shape` (pattern → 3D), no vertex held.
    fn shaped_frame(shape: &dyn Fn(V2) -> V3) -> GeometryFrame {
        let (mut sp, mut sg) = sheet();
        for i in 0..sp.num_vertices() {
            sp.pos[i] = shape(sp.pattern[i]);
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        g.frame().clone()
    }

    fn centre_triangle(sp: &PhysMesh, p: V2) -> usize {
        use crate::sheet::pattern::signed_area as sa;
        (0..sp.num_triangles())
            .find(|&t| {
                let [a, b, c] = sp.triangles[t].map(|i| sp.pattern[i as usize]);
                sa(a, b, p) >= 0.0 && sa(b, c, p) >= 0.0 && sa(c, a, p) >= 0.0
            })
            .unwrap()
    }

    /// Digest §8 test 2 (T 818–826, Fig. 2.5), on the lattice's own quad: two triangles
    /// (u, w, x1), (w, u, x2) sharing the edge e1 = u–w, positions set by hand (the four
    /// corners "held"). Squeezing u and w together by 0.3 % and lifting x1 by 0.35 mm bends
    /// the quad by less than θ0: one flat region, e1 compressed, the other diagonal x1–x2 not,
    /// so the layer asks for e1 to be flipped. On the flipped mesh, folding the quad along the
    /// new diagonal by 0.05 rad (≥ θ0) splits it into two flat regions with a crease between.
    #[test]
    fn a_compressed_flat_edge_is_flipped_and_the_fold_across_it_splits_the_region() {
        let s = 0.1;
        let h = s * 3f64.sqrt() / 2.0;
        let pattern = crate::sheet::pattern::Pattern {
            points: vec![
                V2::new(0.0, 0.0),
                V2::new(s, 0.0),
                V2::new(s / 2.0, h),
                V2::new(s / 2.0, -h),
            ],
            triangles: vec![[0, 1, 2], [1, 0, 3]],
        };
        let mut sp = PhysMesh::from_pattern(&pattern, 0.0, 0.08).unwrap();
        let mut sg = GeomStructure::initial(&sp);
        sp.pos[0].x += 0.0015 * s;
        sp.pos[1].x -= 0.0015 * s;
        sp.pos[2].z += 3.5e-4;
        let mut g = layer(&sp);
        let fixed = vec![false; 4];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let e1 = sp.topo.find_edge(0, 1).unwrap() as usize;
        assert!(g.frame().edge_dihedral_rad[e1].abs() < THETA0_RAD);
        let f = *g.pending_flip().expect("e1 is to be flipped");
        assert_eq!(f.edge, [0, 1]);
        assert!((f.compression - 0.003).abs() < 1e-4, "{}", f.compression);
        assert!(f.other_compression <= 0.0);
        // The same quad squeezed flat in its plane keeps its edge.
        let mut flat = PhysMesh::from_pattern(&pattern, 0.0, 0.08).unwrap();
        flat.pos[0].x += 0.0015 * s;
        flat.pos[1].x -= 0.0015 * s;
        let mut gf = layer(&flat);
        let mut sgf = GeomStructure::initial(&flat);
        gf.update(&mut flat, &mut sgf, &fixed, &obstacles, 1, true, &[]);
        assert!(gf.pending_flip().is_none());
        // The sim's part: flip, carry the layer over.
        let g_taken = g.take_pending_flip();
        assert_eq!(g_taken, Some(f));
        let flip = crate::sheet::refine::flip_edge(&sp, e1 as u32).unwrap();
        assert_eq!(flip.diagonal, [2, 3]);
        let mut sp2 = flip.mesh;
        let mut sg2 = GeomStructure::initial(&sp2);
        let mut g2 = g
            .remeshed(
                &sp2,
                &mut sg2,
                &flip.tri_parent,
                None,
                &PaperMaterial::of(crate::control::Material::Printer),
                1,
            )
            .unwrap();
        g2.edge_flipped(&f, flip.diagonal);
        assert!(g2.frame().events.iter().any(|e| matches!(
            e,
            ShapeEvent::EdgeFlipped {
                diagonal: [2, 3],
                ..
            }
        )));
        // Fold about x1–x2: u turns by 0.05 rad about that line, the other three stay.
        for (i, q) in pattern.points.iter().enumerate() {
            sp2.pos[i] = V3::new(q.x, q.y, 0.0);
        }
        let phi: f64 = 0.05;
        let r = s / 2.0;
        sp2.pos[0] = V3::new(s / 2.0 - r * phi.cos(), 0.0, r * phi.sin());
        g2.update(&mut sp2, &mut sg2, &fixed, &obstacles, 2, true, &[]);
        let e2 = sp2.topo.find_edge(2, 3).unwrap() as usize;
        assert!((g2.frame().edge_dihedral_rad[e2].abs() - phi).abs() < 1e-9);
        let fr = g2.frame();
        assert_eq!(fr.num_flat_regions, 2, "{:?}", fr.regions);
        assert_ne!(fr.tri_region[0], fr.tri_region[1]);
        assert!(g2.pending_flip().is_none(), "nothing is compressed now");
    }

    /// A pending flip is saved with the sheet; a corrupt one is refused.
    #[test]
    fn a_pending_flip_survives_save_and_restore_and_a_corrupt_one_is_refused() {
        let (sp, mut sg) = sheet();
        let mut g = layer(&sp);
        g.pending_flip = Some(PendingFlip {
            edge: [3, 9],
            compression: 0.002,
            other_compression: -0.001,
            frame: 7,
        });
        let saved = g.save();
        let mut r = layer(&sp);
        r.restore(&sp, &mut sg, Some(&saved)).unwrap();
        assert_eq!(r.pending_flip(), g.pending_flip());
        for bad in [
            ([9, 3], 0.002, 0.0, 7),
            ([3, 100_000], 0.002, 0.0, 7),
            ([3, 9], f64::NAN, 0.0, 7),
        ] {
            let mut s2 = saved.clone();
            s2.pending_flip = Some(bad);
            assert!(layer(&sp).restore(&sp, &mut sg, Some(&s2)).is_err());
        }
    }

    /// Digest §8 test 3, case {∂S, ∂S} (Fig. 7): a flat sheet compressed along x gives
    /// rulings parallel to v⊥ = ±y, both borders free, and no singular vertex.
    #[test]
    fn compressed_flat_sheet_propagates_to_two_free_borders() {
        let (mut sp, mut sg) = sheet();
        for i in 0..sp.num_vertices() {
            sp.pos[i].x *= 0.99;
        }
        let mut g = layer(&sp);
        let t = centre_triangle(&sp, V2::new(1.3e-3, 0.7e-3));
        let x = sp.triangles[t].map(|i| sp.pos[i as usize]);
        let s = stretch::stretch_tensor(&x, &sp.tri_rest[t].dm_inv);
        assert!((s.compression() - 0.01).abs() < 1e-9);
        assert!(s.v_perp.x.abs() < 1e-9, "rulings ∥ v⊥ = y: {:?}", s.v_perp);
        g.analyse_shape(&sp);
        g.classify();
        let b = g.propagate(&sp, t as u32, s.v_perp);
        assert_eq!(b, [Border::Free, Border::Free]);
        assert!(
            g.strip.len() >= 8,
            "the strip crosses the sheet: {}",
            g.strip.len()
        );
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        assert!(g.frame().singular.is_empty());
        assert!(
            g.frame()
                .events
                .iter()
                .any(|e| matches!(e, ShapeEvent::StripCurved { cylinder: true, .. }))
        );
    }

    /// Strip cutting (`cut_strips`): the cylinder strip of the compressed flat sheet is cut
    /// along its imaginary ruling, so that the ruling becomes a chain of S_P edges from border
    /// to border; the strip's triangles stay curved on the cut mesh. Off, nothing is pending.
    #[test]
    fn a_new_cylinder_strip_is_cut_along_its_ruling_when_cutting_is_on() {
        let fixed = vec![false; sheet().0.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        let squeezed = || {
            let (mut sp, sg) = sheet();
            for i in 0..sp.num_vertices() {
                sp.pos[i].x *= 0.99;
            }
            (sp, sg)
        };
        let (mut sp, mut sg) = squeezed();
        let mut off = layer(&sp);
        off.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        assert!(off.pending_cut().is_none());

        let (mut sp, mut sg) = squeezed();
        let mut g = layer(&sp);
        g.cfg.cut_strips = true;
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let line = g.pending_cut().expect("the strip is to be cut").to_vec();
        // From border to border, in order along the ruling (v⊥ = ±y).
        let point = |c: &EdgeCrossing| {
            let [a, b] = c.edge.map(|v| sp.pattern[v as usize]);
            a + (b - a) * c.u
        };
        let ys: Vec<f64> = line.iter().map(|c| point(c).y).collect();
        let xs: Vec<f64> = line.iter().map(|c| point(c).x).collect();
        assert!(ys.windows(2).all(|w| w[1] > w[0]) || ys.windows(2).all(|w| w[1] < w[0]));
        assert!(
            xs.iter().all(|x| (x - xs[0]).abs() < 1e-9),
            "a straight ruling ∥ y"
        );
        for end in [&line[0], &line[line.len() - 1]] {
            let e = sp.topo.find_edge(end.edge[0], end.edge[1]).unwrap();
            assert!(sp.topo.edges[e as usize].is_boundary());
        }
        // The sim's part: cut, carry the layer over.
        let strip_tris: Vec<u32> = (0..sp.num_triangles() as u32)
            .filter(|&t| g.curved[t as usize])
            .collect();
        assert!(strip_tris.len() >= 8);
        let (taken, frame) = g.take_pending_cut().unwrap();
        assert_eq!((taken.as_slice(), frame), (line.as_slice(), 1));
        assert!(g.pending_cut().is_none());
        let cut = crate::sheet::cut::cut_along(&sp, &taken).unwrap();
        let m = &cut.mesh;
        let (first, last) = (cut.chain[0], *cut.chain.last().unwrap());
        assert!(m.topo.vertex_on_boundary[first as usize]);
        assert!(m.topo.vertex_on_boundary[last as usize]);
        assert!(cut.chain.len() >= 8);
        for w in cut.chain.windows(2) {
            assert!(m.topo.find_edge(w[0], w[1]).is_some());
        }
        let mut sg2 = GeomStructure::initial(m);
        let mut g2 = g
            .remeshed(
                m,
                &mut sg2,
                &cut.tri_parent,
                None,
                &PaperMaterial::of(crate::control::Material::Printer),
                1,
            )
            .unwrap();
        g2.strip_cut(cut.chain.len() as u32, cut.added as u32);
        assert!(g2.frame().events.iter().any(|e| matches!(
            e,
            ShapeEvent::StripCut { added_vertices, .. } if *added_vertices as usize == cut.added
        )));
        for (t, &p) in cut.tri_parent.iter().enumerate() {
            assert_eq!(g2.curved[t], g.curved[p as usize]);
        }
    }

    #[test]
    fn a_pending_cut_survives_save_and_restore_and_a_corrupt_one_is_refused() {
        let (sp, mut sg) = sheet();
        let mut g = layer(&sp);
        let e = sp.topo.edges[20].v;
        g.pending_cut.extend([
            EdgeCrossing { edge: e, u: 0.4 },
            EdgeCrossing {
                edge: sp.topo.edges[21].v,
                u: 0.5,
            },
        ]);
        g.pending_cut_frame = Some(9);
        let saved = g.save();
        let mut r = layer(&sp);
        r.restore(&sp, &mut sg, Some(&saved)).unwrap();
        assert_eq!(r.pending_cut(), g.pending_cut());
        assert_eq!(r.save(), saved);
        for bad in [
            vec![([e[0], e[0]], 0.4)],
            vec![([e[0], 100_000], 0.4)],
            vec![(e, f64::NAN)],
            vec![(e, 1.5)],
            vec![(e, 0.5); 2000],
        ] {
            let mut s2 = saved.clone();
            s2.pending_cut = Some((bad, 9));
            assert!(layer(&sp).restore(&sp, &mut sg, Some(&s2)).is_err());
        }
    }

    #[test]
    fn a_pending_coarsening_survives_save_and_restore_and_a_corrupt_one_is_refused() {
        let (sp, mut sg) = sheet();
        let nv = sp.num_vertices() as u32;
        let mut g = layer(&sp);
        // Pretend the last four vertices came after the lattice.
        g.coarsen_from = nv as usize - 4;
        g.pending_coarsen = Some((nv - 2, 40));
        let saved = g.save();
        let mut r = layer(&sp);
        r.restore(&sp, &mut sg, Some(&saved)).unwrap();
        assert_eq!(r.pending_coarsen(), Some(nv - 2));
        assert_eq!(r.save(), saved);
        // A lattice vertex, a vertex out of range, a lattice larger than the mesh.
        for (from, pending) in [
            (Some(nv - 4), Some((nv - 5, 40))),
            (Some(nv - 4), Some((nv, 40))),
            (Some(nv + 1), None),
        ] {
            let mut s2 = saved.clone();
            s2.coarsen_from = from;
            s2.pending_coarsen = pending;
            assert!(layer(&sp).restore(&sp, &mut sg, Some(&s2)).is_err());
        }
        // A save from before coarsening: every vertex present stays.
        let mut old = saved.clone();
        old.coarsen_from = None;
        old.pending_coarsen = None;
        let mut o = layer(&sp);
        o.restore(&sp, &mut sg, Some(&old)).unwrap();
        assert_eq!(o.coarsen_from, sp.num_vertices());
        assert_eq!(o.pending_coarsen(), None);
    }

    /// Digest §8 test 3, case {∂S, singular on a crease} (Fig. 6c): a sheet folded along a
    /// lattice row into two flat regions, compressed across the fold, gets a singular vertex
    /// next to the crease, with fibre damage around it; the crease is published as a ruling.
    #[test]
    fn propagation_into_a_crease_creates_a_singular_vertex() {
        let (mut sp, mut sg) = sheet();
        // The lattice row nearest y = 0.
        let y0 = sp
            .pattern
            .iter()
            .map(|q| q.y)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap();
        let ang: f64 = 0.3;
        for i in 0..sp.num_vertices() {
            let q = sp.pattern[i];
            let x = q.x * 0.995;
            sp.pos[i] = if q.y > y0 + 1e-9 {
                let d = q.y - y0;
                V3::new(x, y0 + d * ang.cos(), d * ang.sin())
            } else {
                V3::new(x, q.y, 0.0)
            };
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let f = g.frame();
        assert!(
            f.num_flat_regions >= 2,
            "{} flat regions",
            f.num_flat_regions
        );
        assert!(f.num_creases >= 1);
        assert!(
            f.rulings
                .iter()
                .any(|r| r.sp_edge != NONE && (r.dihedral_rad.abs() - ang).abs() < 1e-6)
        );
        assert_eq!(f.singular.len(), 1);
        let s = f.singular[0];
        assert_eq!(s.case, SingularCase::Crease);
        // Next to the crease (within one edge of the fold row), 2D position fixed.
        assert!((s.pos2.y - y0).abs() < 0.012, "{:?}", s.pos2);
        assert!((s.sampled2.y - y0).abs() < 0.01);
        let n = sp.topo.valence(s.sp_vertex) as f64;
        for &j in sp.topo.neighbours(s.sp_vertex) {
            let e = sp.topo.find_edge(s.sp_vertex, j).unwrap() as usize;
            assert!((sp.edge_rest_angle[e].abs() - THETA_REST_RAD / n).abs() < 1e-12);
            assert!((sp.edge_damage[e] - DAMAGE_D / n).abs() < 1e-12);
        }
        assert_eq!(sg.num_singular(), 1);
    }

    /// A region containing a singular vertex is one cone with that apex; curved regions of a
    /// bent sheet have rulings along the bend's generators and free borders.
    #[test]
    fn bent_sheet_has_a_curved_region_with_generator_rulings() {
        let (mut sp, mut sg) = sheet();
        let r = 0.05;
        for i in 0..sp.num_vertices() {
            let q = sp.pattern[i];
            let a = q.x / r;
            sp.pos[i] = V3::new(r * a.sin(), q.y, r * (1.0 - a.cos()));
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let f = g.frame();
        assert!(f.num_curved_regions >= 1);
        let big = f
            .regions
            .iter()
            .enumerate()
            .max_by_key(|(_, r)| r.num_triangles)
            .unwrap();
        assert_eq!(big.1.kind, RegionKind::Curved);
        let rs = f.region_rulings(big.0 as u32);
        assert!(rs.len() >= 3);
        for q in rs {
            let d = (q.b2 - q.a2).normalize();
            assert!(d.y.abs() > 0.95, "generator ∥ y: {d:?}");
        }
        assert!(big.1.free_border_len_m > 0.05);
        assert!(big.1.mean_ruling_len_m > 0.05);
        assert!(
            f.cones
                .iter()
                .any(|c| c.region == big.0 as u32 && !c.is_gap)
        );
        assert!(f.singular.is_empty());
    }

    /// Digest §8 test 6 (ruling realignment and boundary resampling, P 871–884, T 1103–1112):
    /// a sheet rolled onto a circular cone whose apex lies 10 cm off its edge. Every ruling of a
    /// fitted cone passes within 1e-6 cm of the cone's pattern apex ā_proj, which lies near
    /// the true apex; neighbouring rulings' border ends are ≤ 1/ρ_bound apart; a rolled
    /// cylinder's rulings come out parallel.
    #[test]
    fn rulings_are_realigned_to_their_cone_and_the_border_resampled() {
        let run = shaped_frame;
        // A circular cone of half-angle α with its apex at the origin, unrolled about the
        // pattern point `apex`: generator angle φ → ψ = φ / sin α around the axis (isometric).
        let apex = V2::new(-0.15, 0.0);
        let (sin_a, cos_a) = (0.6f64, 0.8f64);
        let cone = |q: V2| {
            let d = q - apex;
            let (r, psi) = (d.norm(), d.y.atan2(d.x) / sin_a);
            V3::new(r * cos_a, r * sin_a * psi.cos(), r * sin_a * psi.sin())
        };
        let f = run(&cone);
        let gap_max = 1.0 / RHO_BOUND_PER_M + 1e-9;
        let on_edge = |p: V2| 0.05 - p.x.abs().max(p.y.abs()) < 1e-9;
        let (mut checked, mut gaps, mut short, mut edge_gaps, mut edge_short) = (0, 0, 0, 0, 0);
        // (A stray curved triangle at the border may form a one-ruling region of its own.)
        for c in f
            .cones
            .iter()
            .filter(|c| !c.is_gap && c.last_ruling > c.first_ruling + 1)
        {
            let a = c.apex2.expect("a cone, not a cylinder");
            assert!((a - apex).norm() < 0.01, "fitted apex {a:?}, true {apex:?}");
            let rs = &f.rulings[c.first_ruling as usize..=c.last_ruling as usize];
            for (k, r) in rs.iter().enumerate() {
                let d = (r.b2 - r.a2).normalize();
                let off = (a - r.a2).perp(&d).abs();
                assert!(off < 1e-8, "ruling {k} misses ā by {off} m");
                checked += 1;
                if k == 0 {
                    continue;
                }
                // Ends on the same straight sheet edge: the resampled spacing holds exactly.
                let p = &rs[k - 1];
                for (e, g) in [(p.a2, r.a2), (p.b2, r.b2)] {
                    let gap = (e - g).norm();
                    gaps += 1;
                    short += usize::from(gap <= gap_max);
                    let same_edge = on_edge(e)
                        && on_edge(g)
                        && ((e.x - g.x).abs() < 1e-9 || (e.y - g.y).abs() < 1e-9);
                    if same_edge {
                        edge_gaps += 1;
                        edge_short += usize::from(gap <= gap_max);
                        // Rulings planned on a chord across a corner land a little farther
                        // apart on the border (module doc).
                        assert!(
                            gap <= 1.25 * gap_max,
                            "gap {gap} m on the sheet edge at ruling {k}: {e:?} {g:?}"
                        );
                    }
                }
            }
        }
        // Inside the sheet, a region's border is ragged where a crease cuts into it, and
        // neighbouring rulings end at different depths: most gaps still meet 1/ρ.
        assert!(edge_gaps >= 10, "{edge_gaps} gaps on the sheet edge");
        assert!(
            10 * edge_short >= 9 * edge_gaps,
            "{edge_short} of {edge_gaps} gaps on the sheet edge ≤ 1/ρ"
        );
        assert!(
            10 * short >= 8 * gaps,
            "{short} of {gaps} border gaps ≤ 1/ρ"
        );
        assert!(checked >= 10, "{checked} rulings checked");
        assert!(f.rulings.iter().any(|r| r.resampled));
        // Resampled rulings are traced on S_P too: their ends lie as close to the true cone
        // as the others' (S_P's chords sag by l²/8R ≈ 0.25 mm here).
        let err = |resampled: bool| {
            f.rulings
                .iter()
                .filter(|r| r.resampled == resampled && r.sp_edge == NONE)
                .flat_map(|r| [(r.a2, r.a3), (r.b2, r.b3)])
                .map(|(p2, p3)| (cone(p2) - p3).norm())
                .fold(0.0, f64::max)
        };
        let (e_resampled, e_traced) = (err(true), err(false));
        assert!(e_resampled <= 1.5 * e_traced, "{e_resampled} vs {e_traced}");
        // A cylinder (rolled about y): parallel rulings along y.
        let radius = 0.05;
        let f = run(&|q: V2| {
            let t = q.x / radius;
            V3::new(radius * t.sin(), q.y, radius * (1.0 - t.cos()))
        });
        let mut parallel = 0;
        let big = (0..f.regions.len())
            .max_by_key(|&r| f.regions[r].num_triangles)
            .unwrap() as u32;
        for c in f
            .cones
            .iter()
            .filter(|c| c.region == big && !c.is_gap && c.apex2.is_none())
        {
            let rs = &f.rulings[c.first_ruling as usize..=c.last_ruling as usize];
            let d0 = (rs[0].b2 - rs[0].a2).normalize();
            for r in rs {
                let d = (r.b2 - r.a2).normalize();
                assert!(
                    d.perp(&d0).abs() < 1e-9,
                    "cylinder rulings not parallel: {d:?} {d0:?}"
                );
                assert!(d.x.abs() < 0.05, "cylinder ruling not along y: {d:?}");
                parallel += 1;
            }
        }
        assert!(parallel >= 5, "{parallel} rulings in cylinders");
    }

    /// S_G of a frame ([`GeometryFrame::sg_vertices`]): a sheet flat for x < 0 and rolled for
    /// x > 0, held at two vertices, lists its corners and boundary samples, a junction point
    /// on each border the bend crosses, the held vertices as handles, and, once two folds
    /// cross, the new singular vertex — each at its S_P vertex's pattern and 3D position.
    #[test]
    fn frame_lists_every_kind_of_sg_vertex_with_its_positions() {
        let obstacles = Obstacles::new(&RoomConfig::default());
        let check = |shape: &dyn Fn(V2) -> V3, held: &[usize]| {
            let (mut sp, mut sg) = sheet();
            for i in 0..sp.num_vertices() {
                sp.pos[i] = shape(sp.pattern[i]);
            }
            let mut g = layer(&sp);
            let mut fixed = vec![false; sp.num_vertices()];
            for &v in held {
                fixed[v] = true;
            }
            g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
            sg.validate(&sp).unwrap();
            let mut count = [0usize; 5];
            for v in g.frame().sg_vertices(&sg, &sp) {
                let i = v.sp_index as usize;
                assert_eq!(v.p2, sp.pattern[i]);
                assert_eq!(v.p3, sp.pos[i]);
                let on_boundary = sp.topo.vertex_on_boundary[i];
                match v.kind {
                    VKind::Boundary | VKind::Corner | VKind::Junction => assert!(on_boundary),
                    VKind::InteriorSingular => assert!(!on_boundary),
                    VKind::Handle => assert!(fixed[i]),
                }
                count[v.kind as usize] += 1;
            }
            count
        };
        let r = 0.02;
        let half_roll = |q: V2| {
            if q.x <= 0.0 {
                V3::new(q.x, q.y, 0.0)
            } else {
                let a = q.x / r;
                V3::new(r * a.sin(), q.y, r * (1.0 - a.cos()))
            }
        };
        let [boundary, corner, singular, junction, handle] = check(&half_roll, &[0, 5]);
        assert!(boundary >= 4, "{boundary} boundary samples");
        assert_eq!(corner, 4);
        assert_eq!(singular, 0);
        assert!(
            junction >= 2,
            "{junction} junction points: the bend crosses two borders"
        );
        assert_eq!(handle, 2);
        let roof = |q: V2| V3::new(q.x, q.y, 0.5 * (q.x.abs() + q.y.abs()));
        let [_, _, singular, _, handle] = check(&roof, &[]);
        assert!(
            singular >= 1,
            "the crossing of two folds is a singular vertex"
        );
        assert_eq!(handle, 0);
    }

    /// The non-developable-vertex detector: a sheet bent along one direction only (a tight
    /// cylinder) has no singular vertex, one folded along two crossing lines (a pyramid-like
    /// roof, z = a(|x| + |y|)) gets one at the crossing.
    #[test]
    fn crossing_bends_make_a_singular_vertex_and_a_cylinder_does_not() {
        let run = |shape: &dyn Fn(V2) -> V3| {
            shaped_frame(shape)
                .singular
                .iter()
                .filter(|s| s.case == SingularCase::NonDevelopable)
                .map(|s| s.pos2)
                .collect::<Vec<_>>()
        };
        let r = 0.02;
        let cylinder = run(&|q: V2| {
            let a = q.x / r;
            V3::new(r * a.sin(), q.y, r * (1.0 - a.cos()))
        });
        assert!(cylinder.is_empty(), "{cylinder:?}");
        let c = 0.0; // the pattern is centred on the origin
        let roof = run(&|q: V2| V3::new(q.x, q.y, 0.5 * ((q.x - c).abs() + (q.y - c).abs())));
        assert!(!roof.is_empty(), "no singular vertex where two folds cross");
        let p = roof[0];
        assert!((p - V2::new(c, c)).norm() < 0.02, "at {p:?}");
    }

    /// A rounded fold running obliquely across the lattice: two flat regions, no one-triangle
    /// flat region between the fold's zigzag edges, and the fold itself a few regions (a
    /// curved strip and the creases beside it), not one per S_P edge.
    #[test]
    fn oblique_fold_is_two_flat_regions_and_one_fold() {
        let (mut sp, mut sg) = sheet();
        let n = V2::new(1.0, 0.35).normalize();
        for i in 0..sp.num_vertices() {
            let q = sp.pattern[i];
            let d = q.dot(&n) - 0.004;
            // The far side turns by 0.8 rad over a rounded band 2.5 cm wide (two to three
            // rows of triangles), as a fold of the simulated sheet does.
            let (w, turn) = (0.025, 0.8f64);
            let r = w / turn;
            let (along, z) = if d <= 0.0 {
                (d, 0.0)
            } else if d < w {
                (r * (d / r).sin(), r * (1.0 - (d / r).cos()))
            } else {
                let (c, s) = (turn.cos(), turn.sin());
                (
                    r * turn.sin() + (d - w) * c,
                    r * (1.0 - turn.cos()) + (d - w) * s,
                )
            };
            let t = q - n * q.dot(&n);
            let p2 = t + n * (along + 0.004);
            sp.pos[i] = V3::new(p2.x, p2.y, z);
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let f = g.frame();
        let flats: Vec<u32> = f
            .regions
            .iter()
            .filter(|r| r.kind == RegionKind::Flat)
            .map(|r| r.num_triangles)
            .collect();
        let fold = f.regions.len() - flats.len();
        println!("flat regions {flats:?}, fold regions {fold}");
        assert_eq!(flats.len(), 2, "{flats:?}");
        assert!(flats.iter().all(|&n| n >= 20), "{flats:?}");
        assert!((1..=3).contains(&fold), "{fold} fold regions");
    }

    /// A test sheet with the default layer (isometry on), squeezed along x and stepped one
    /// still or driven frame at a time.
    struct IsoRig {
        sp: PhysMesh,
        sg: GeomStructure,
        flat: Vec<V3>,
        layer: GeometryLayer,
        frame: u64,
    }

    impl IsoRig {
        fn new() -> Self {
            let (sp, sg) = sheet();
            let layer = GeometryLayer::new(
                &sp,
                GeometryConfig::default(),
                &PaperMaterial::of(crate::control::Material::Printer),
                1,
            );
            let flat = sp.pos.clone();
            Self {
                sp,
                sg,
                flat,
                layer,
                frame: 0,
            }
        }

        /// Places the sheet squeezed by `squeeze` along x, runs one frame and returns whether
        /// the isometry step ran.
        fn runs(&mut self, squeeze: f64, driven: bool) -> bool {
            self.place(squeeze, 0.0);
            self.step(driven, &[]);
            self.layer.frame().isometry.phase1_iters > 0
        }

        /// Places the sheet squeezed by `squeeze` along x and rippled by `ripple_m` in z.
        fn place(&mut self, squeeze: f64, ripple_m: f64) {
            for (p, q) in self.sp.pos.iter_mut().zip(&self.flat) {
                let z = ripple_m * (40.0 * q.x).sin() * (25.0 * q.y).cos();
                *p = V3::new(q.x * (1.0 - squeeze), q.y, q.z + z);
            }
        }

        /// Runs one frame with `start_normals` as the frame's start.
        fn step(&mut self, driven: bool, start_normals: &[V3]) {
            self.frame += 1;
            let fixed = vec![false; self.sp.num_vertices()];
            let obstacles = Obstacles::new(&RoomConfig::default());
            self.layer.update(
                &mut self.sp,
                &mut self.sg,
                &fixed,
                &obstacles,
                self.frame,
                driven,
                start_normals,
            );
        }

        /// Unit normals of the triangles.
        fn normals(&self) -> Vec<V3> {
            self.sp
                .triangles
                .iter()
                .map(|t| {
                    let x = t.map(|i| self.sp.pos[i as usize]);
                    (x[1] - x[0]).cross(&(x[2] - x[0])).normalize()
                })
                .collect()
        }
    }

    /// The isometry step never turns a triangle over from the frame's start, even one the
    /// physics left at 90° from it: here the start normal of the triangle the step turns most
    /// is set perpendicular to its normal before the step, on the side the step turns away
    /// from, and the step is reverted.
    #[test]
    fn isometry_never_turns_a_triangle_over_from_the_frame_start() {
        let mut free = IsoRig::new();
        free.place(0.02, 2e-3);
        let before = free.normals();
        free.step(true, &before);
        assert!(!free.layer.frame().isometry_reverted);
        let after = free.normals();
        let (t, turn) = (0..before.len())
            .map(|t| (t, 1.0 - before[t].dot(&after[t])))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        assert!(turn > 1e-9, "the step turns triangle {t} ({turn:e})");
        let mut start = before.clone();
        let away = after[t] - before[t] * after[t].dot(&before[t]);
        start[t] = (-away.normalize() + before[t] * 1e-9).normalize();
        let mut rig = IsoRig::new();
        rig.place(0.02, 2e-3);
        rig.step(true, &start);
        assert!(rig.layer.frame().isometry_reverted);
        assert!(
            !rig.layer.checked_uncrossed(),
            "reverted before the crossing test"
        );
        let n = rig.normals();
        assert!(n[t].dot(&start[t]) >= 0.0, "triangle {t} not turned over");
        assert!(
            (n[t] - before[t]).norm() < 1e-12,
            "triangle {t} kept as before the step"
        );
    }

    /// The isometry step tells the sim when it has already found the final positions
    /// uncrossed (the pass-through guard then skips its own sweep): after a step that ran its
    /// crossing test, not after one that did not run or was reverted before the test.
    #[test]
    fn isometry_reports_positions_it_found_uncrossed() {
        let mut rig = IsoRig::new();
        rig.place(0.02, 2e-3);
        let n = rig.normals();
        rig.step(true, &n);
        assert!(!rig.layer.frame().isometry_reverted);
        assert!(rig.layer.checked_uncrossed());
        let crossed = rig.layer.proximity.any_crossing(&rig.sp);
        assert!(!crossed, "the positions left are uncrossed");
        // Reverted before the test: `isometry_never_turns_a_triangle_over_from_the_frame_start`.
        // Idle frame: nothing checked.
        rig.layer.idle_frame(99);
        assert!(!rig.layer.checked_uncrossed());
    }

    /// The isometry step's trigger (isometry.rs "When it runs"): on a still sheet (no
    /// gesture moving it) it runs only if some edge is compressed by more than 1 %; while a
    /// gesture drives the sheet it runs every frame.
    #[test]
    fn isometry_runs_when_driven_or_compressed_beyond_the_trigger() {
        let runs = |squeeze: f64, driven: bool| IsoRig::new().runs(squeeze, driven);
        assert!(
            !runs(0.005, false),
            "0.5 % on a still sheet: physics' equilibrium kept"
        );
        assert!(runs(0.005, true), "0.5 % while a gesture drives the sheet");
        assert!(runs(0.02, false), "2 % on a still sheet");
    }

    /// Undriven, the isometry step corrects a compression once; the physics rebuilding the
    /// same compression (the hands' doing) does not make it run again, a 10 % larger one,
    /// a driven frame or a relief below the trigger does.
    #[test]
    fn isometry_skips_a_compression_it_already_met() {
        let mut rig = IsoRig::new();
        let mut runs = |squeeze: f64, driven: bool| rig.runs(squeeze, driven);
        assert!(runs(0.02, false), "first undriven 2 %");
        assert!(!runs(0.02, false), "the same 2 % rebuilt");
        assert!(!runs(0.021, false), "5 % more");
        assert!(runs(0.023, false), "15 % more");
        assert!(!runs(0.023, false), "that one rebuilt");
        assert!(runs(0.023, true), "driven");
        assert!(runs(0.02, false), "undriven after a driven frame");
        assert!(!runs(0.005, false), "below the trigger");
        assert!(runs(0.02, false), "2 % again after a relief");
    }
}
