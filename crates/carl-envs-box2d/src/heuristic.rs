//! Gymnasium's hand-written LunarLander controller (`gymnasium.envs.box2d.lunar_lander.heuristic`),
//! re-implemented from its control law: steer the angle towards the pad, hover at a height
//! proportional to the horizontal offset, and after touchdown only brake the fall.

/// The two control errors `(angle_todo, hover_todo)` for observation `s`.
pub fn control_errors(s: &[f32]) -> (f64, f64) {
    let g = |i: usize| s.get(i).copied().unwrap_or(0.0) as f64;
    // Point towards the centre, at most 0.4 rad (22°) of tilt.
    let angle_targ = (g(0) * 0.5 + g(2)).clamp(-0.4, 0.4);
    let hover_targ = 0.55 * g(0).abs();
    let mut angle_todo = (angle_targ - g(4)) * 0.5 - g(5);
    let mut hover_todo = (hover_targ - g(1)) * 0.5 - g(3) * 0.5;
    if g(6) != 0.0 || g(7) != 0.0 {
        // After touchdown: keep the attitude, only reduce the fall speed.
        angle_todo = 0.0;
        hover_todo = -g(3) * 0.5;
    }
    (angle_todo, hover_todo)
}

/// Discrete action (0 noop, 1 left engine, 2 main engine, 3 right engine).
pub fn heuristic(s: &[f32]) -> i64 {
    let (angle_todo, hover_todo) = control_errors(s);
    if hover_todo > angle_todo.abs() && hover_todo > 0.05 {
        2
    } else if angle_todo < -0.05 {
        3
    } else if angle_todo > 0.05 {
        1
    } else {
        0
    }
}

/// Continuous action `[main, lateral]` clipped to `[-1, 1]`.
pub fn heuristic_continuous(s: &[f32]) -> [f32; 2] {
    let (angle_todo, hover_todo) = control_errors(s);
    [
        (hover_todo * 20.0 - 1.0).clamp(-1.0, 1.0) as f32,
        (-angle_todo * 20.0).clamp(-1.0, 1.0) as f32,
    ]
}
