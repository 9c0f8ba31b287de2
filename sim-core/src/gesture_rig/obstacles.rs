//! # Hands and obstacles: targets moved out of the table, wall and floor, and hands carried along
//! by a moving obstacle (the parent module's doc, "Obstacles").

use super::*;

impl GestureRig {
    /// Moves a target pose out of the obstacles: the held patch (as grabbed) at that pose is
    /// shifted along each plane's normal until none of its vertices is inside. The hand then
    /// travels there at its own speed, so a patch grabbed inside an obstacle (or overtaken by
    /// a moving table) comes out gradually instead of jumping.
    pub(super) fn pushed_out(&self, k: usize, target: Pose, obstacles: &Obstacles) -> Pose {
        let r = target.rotation();
        let mut p = target.pos();
        for pl in obstacles.planes.iter() {
            if !pl.active {
                continue;
            }
            let push = self.held_depth_m(k, p, &r, pl);
            if push > 0.0 {
                p += pl.normal * push;
            }
        }
        Pose::new(p, r)
    }

    /// How deep the deepest vertex held by hand `k` lies inside plane `pl` with the hand at
    /// `pos`, `rot`, metres (negative: all outside; −∞ if it holds none).
    pub(super) fn held_depth_m(&self, k: usize, pos: V3, rot: &Rot, pl: &PlaneObstacle) -> f64 {
        let h = &self.state.hands[k];
        (0..self.info[k].def.num_vertices as usize)
            .filter(|&j| h.holds(j))
            .map(|j| -pl.distance(&(pos + rot * V3::from(h.offsets_m[j]))))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// A plane moving into a held patch (a table being raised) carries the hands along its
    /// normal, by at most the plane's own motion this frame. It carries **every** active hand
    /// by the largest push any of them needs: the hands hold one sheet and yield to the table
    /// together. Carrying only the hands it touches would pin their vertices to the rising
    /// table top while the layers of a held crumpled ball above them are pushed up by the
    /// table through the layers below: the sheet between is pulled apart and held vertices
    /// slip into the table (docs/decisions.md, "Hands, grip and obstacles"). Returns true
    /// if it moved any hand.
    pub(super) fn carried_by_obstacles(&mut self, obstacles: &Obstacles, dt_s: f64) -> bool {
        let mut moved = false;
        for pl in obstacles.planes.iter() {
            if !pl.active || pl.speed_m_s <= 0.0 {
                continue;
            }
            let mut pen: f64 = 0.0;
            for k in 0..NUM_HANDS {
                let h = &self.state.hands[k];
                if !h.active || self.suppressed[k] {
                    continue;
                }
                pen = pen.max(self.held_depth_m(k, h.pose.pos(), &h.pose.rotation(), pl));
            }
            let push = pen.min(pl.speed_m_s * dt_s);
            if push > 0.0 {
                for k in 0..NUM_HANDS {
                    let h = &mut self.state.hands[k];
                    if h.active && !self.suppressed[k] {
                        h.pose = Pose::new(h.pose.pos() + pl.normal * push, h.pose.rotation());
                    }
                }
                moved = true;
            }
        }
        moved
    }
}
