//! The world and its tick (engine_behaviour.md §4–§11): f32 arithmetic in the documented order,
//! no fused multiply-adds.
//!
//! Sprites live in an arena (`sprites`, indexed by id) and the game order is the id list `list`;
//! sprite 0 is always Mario.

use super::level::{self, Level, kind};

/// Game status.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Running,
    Win,
    Lose,
    TimeOut,
}

impl Status {
    /// Digest code: 0 running, 1 win, 2 lose, 3 time-out.
    pub fn code(self) -> u8 {
        match self {
            Status::Running => 0,
            Status::Win => 1,
            Status::Lose => 2,
            Status::TimeOut => 3,
        }
    }
}

/// Event types (§10).
pub mod event {
    pub const BUMP: u8 = 1;
    pub const STOMP_KILL: u8 = 2;
    pub const FIRE_KILL: u8 = 3;
    pub const SHELL_KILL: u8 = 4;
    pub const FALL_KILL: u8 = 5;
    pub const JUMP: u8 = 6;
    pub const LAND: u8 = 7;
    pub const COLLECT: u8 = 8;
    pub const HURT: u8 = 9;
    pub const KICK: u8 = 10;
    pub const LOSE: u8 = 11;
    pub const WIN: u8 = 12;
}

/// One event of the last executed tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Event {
    pub kind: u8,
    pub param: i32,
}

/// The five buttons of a tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Buttons {
    pub left: bool,
    pub right: bool,
    pub down: bool,
    pub speed: bool,
    pub jump: bool,
}

/// A sprite's state (all kinds share one layout; unused fields stay 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Sprite {
    /// Type value (§3): -31 Mario, 2..=16 others; winged enemies keep their odd value.
    pub kind: i32,
    pub x: f32,
    pub y: f32,
    pub xa: f32,
    pub ya: f32,
    pub w: i32,
    pub h: i32,
    pub facing: i32,
    pub alive: bool,
    pub on_ground: bool,
    pub winged: bool,
    /// Spawn code `(tx, ty, type)` of the template the sprite came from.
    pub origin: Option<(i32, i32, i32)>,
    /// Flower: resting y and wait counter; items: life counter.
    pub y_start: f32,
    pub wait: i32,
    pub life: i32,
}

impl Sprite {
    fn new(kind: i32, x: f32, y: f32, w: i32, h: i32) -> Self {
        Sprite {
            kind,
            x,
            y,
            xa: 0.0,
            ya: 0.0,
            w,
            h,
            facing: 0,
            alive: true,
            on_ground: false,
            winged: false,
            origin: None,
            y_start: 0.0,
            wait: 0,
            life: 0,
        }
    }

    fn is_enemy(&self) -> bool {
        (kind::GOOMBA..=kind::FLOWER).contains(&self.kind)
    }

    fn is_walker(&self) -> bool {
        (kind::GOOMBA..=kind::SPIKY_WINGED).contains(&self.kind)
    }

    fn is_spiky(&self) -> bool {
        self.kind == kind::SPIKY || self.kind == kind::SPIKY_WINGED
    }
}

/// Mario's state beyond his sprite fields.
#[derive(Debug, Clone, PartialEq)]
pub struct MarioState {
    pub was_on_ground: bool,
    pub is_large: bool,
    pub is_fire: bool,
    pub is_ducking: bool,
    pub may_jump: bool,
    pub can_shoot: bool,
    pub jump_time: i32,
    pub invulnerable: i32,
    pub x_jump_start: f32,
    /// Inertia `k` (CARL's `mario_inertia` as f32).
    pub inertia: f32,
    pub buttons: Buttons,
}

const MARIO: usize = 0;

/// The game world.
#[derive(Debug, Clone)]
pub struct World {
    pub level: Level,
    pub status: Status,
    /// Milliseconds left; ≤ 0 at the start means no limit.
    pub timer: i32,
    pub pause: i32,
    pub tick_count: i32,
    pub cam_x: f32,
    pub cam_y: f32,
    pub coins: i32,
    pub lives: i32,
    pub events: Vec<Event>,
    pub sprites: Vec<Sprite>,
    pub list: Vec<usize>,
    pub mario: MarioState,
    added: Vec<usize>,
    removed: Vec<usize>,
    shell_checks: Vec<usize>,
    fireball_checks: Vec<usize>,
    fireballs_on_screen: i32,
    last_seen: Vec<i32>,
    /// Sub-step iterations of the current move (guards the inertia ≥ 1 hazard, §16).
    substeps: u32,
}

/// Largest number of 8-px sub-steps one move may take. Far beyond any reachable speed in a
/// 1000-tile level (16,000 px = 2,000 sub-steps); only reached when `x ± 8 == x` in f32
/// (speeds near 2^28), where the oracle would loop forever. The move then counts as blocked.
pub const MAX_SUBSTEPS: u32 = 1 << 20;

impl World {
    /// A world at its creation (before the reset tick): `timer_seconds` × 1000 ms.
    pub fn new(level: Level, timer_seconds: i32, inertia: f32, is_large: bool, is_fire: bool) -> Self {
        let (sx, sy) = level.start;
        let mario = Sprite {
            facing: 1,
            ..Sprite::new(kind::MARIO, (16 * sx) as f32 + 8.0, (16 * sy) as f32 + 15.0, 4, 24)
        };
        let n = level.width * level.height;
        World {
            level,
            status: Status::Running,
            timer: timer_seconds.saturating_mul(1000),
            pause: 0,
            tick_count: 0,
            cam_x: 0.0,
            cam_y: 0.0,
            coins: 0,
            lives: 0,
            events: Vec::new(),
            sprites: vec![mario],
            list: vec![MARIO],
            mario: MarioState {
                was_on_ground: false,
                is_large,
                is_fire,
                is_ducking: false,
                may_jump: false,
                can_shoot: false,
                jump_time: 0,
                invulnerable: 0,
                x_jump_start: -100.0,
                inertia,
                buttons: Buttons::default(),
            },
            added: Vec::new(),
            removed: Vec::new(),
            shell_checks: Vec::new(),
            fireball_checks: Vec::new(),
            fireballs_on_screen: 0,
            last_seen: vec![-40; n],
            substeps: 0,
        }
    }

    pub fn mario(&self) -> &Sprite {
        &self.sprites[MARIO]
    }

    fn width_px(&self) -> i32 {
        16 * self.level.width as i32
    }

    fn height_px(&self) -> i32 {
        16 * self.level.height as i32
    }

    fn event(&mut self, kind: u8, param: i32) {
        self.events.push(Event { kind, param });
    }

    // ------------------------------------------------------------------ the tick (§4)

    /// One engine tick with these buttons.
    pub fn tick(&mut self, buttons: Buttons) {
        if self.status != Status::Running {
            return;
        }
        if self.pause > 0 {
            self.pause -= 1;
            return;
        }
        if self.timer > 0 {
            self.timer -= 30;
            if self.timer <= 0 {
                self.timer = 0;
                self.status = Status::TimeOut;
                self.sprites[MARIO].alive = false;
                return;
            }
        }
        self.tick_count += 1;
        // Camera from Mario's position at the end of the previous tick.
        let (mx, my) = (self.sprites[MARIO].x, self.sprites[MARIO].y);
        self.cam_x = mx - 128.0;
        if self.cam_x + 256.0 > self.width_px() as f32 {
            self.cam_x = (self.width_px() - 256) as f32;
        }
        if self.cam_x < 0.0 {
            self.cam_x = 0.0;
        }
        self.cam_y = my - 128.0;
        if self.cam_y + 256.0 > self.height_px() as f32 {
            self.cam_y = (self.height_px() - 256) as f32;
        }
        if self.cam_y < 0.0 {
            self.cam_y = 0.0;
        }
        self.events.clear();
        self.fireballs_on_screen = 0;
        self.despawn_pass();
        self.spawn_pass();
        self.mario.buttons = buttons;
        for i in 0..self.list.len() {
            let id = self.list[i];
            if self.sprites[id].alive {
                self.update(id);
            }
        }
        for i in 0..self.list.len() {
            let id = self.list[i];
            if self.sprites[id].alive {
                self.contact(id);
            }
        }
        let shells = std::mem::take(&mut self.shell_checks);
        for &shell in &shells {
            for i in 0..self.list.len() {
                let s = self.list[i];
                if s != shell && self.sprites[shell].alive && self.sprites[s].alive && self.shell_rule(s, shell) {
                    self.remove(s);
                }
            }
        }
        let fireballs = std::mem::take(&mut self.fireball_checks);
        for &fb in &fireballs {
            for i in 0..self.list.len() {
                let s = self.list[i];
                if s != fb && self.sprites[fb].alive && self.sprites[s].alive && self.fireball_rule(s, fb) {
                    self.remove(fb);
                }
            }
        }
        // List maintenance: new sprites to the front, in creation order; removed ones deleted.
        if !self.added.is_empty() {
            let mut list = std::mem::take(&mut self.added);
            list.extend_from_slice(&self.list);
            self.list = list;
        }
        if !self.removed.is_empty() {
            let removed = std::mem::take(&mut self.removed);
            self.list.retain(|id| !removed.contains(id));
        }
        self.compact_if_needed();
    }

    /// Drops dead sprites from the arena once it has grown (ids are renumbered; Mario stays 0).
    fn compact_if_needed(&mut self) {
        if self.sprites.len() < 256 || self.sprites.len() < 4 * self.list.len() {
            return;
        }
        let mut new_id = vec![usize::MAX; self.sprites.len()];
        let mut sprites = Vec::with_capacity(self.list.len() + 16);
        sprites.push(self.sprites[MARIO].clone());
        new_id[MARIO] = MARIO;
        for &id in &self.list {
            if id != MARIO {
                new_id[id] = sprites.len();
                sprites.push(self.sprites[id].clone());
            }
        }
        for id in &mut self.list {
            *id = new_id[*id];
        }
        self.sprites = sprites;
    }

    fn despawn_pass(&mut self) {
        let (cx, h32) = (self.cam_x, (self.height_px() + 32) as f32);
        for i in 0..self.list.len() {
            let id = self.list[i];
            let s = &self.sprites[id];
            if s.x < cx - 64.0 || s.x > cx + 256.0 + 64.0 || s.y > h32 {
                let fall_kill = s.is_enemy() && s.y > 288.0;
                let kind = s.kind;
                if id == MARIO {
                    self.lose();
                }
                self.remove(id);
                if fall_kill {
                    self.event(event::FALL_KILL, kind);
                }
            } else if s.kind == kind::FIREBALL {
                self.fireballs_on_screen += 1;
            }
        }
    }

    fn spawn_pass(&mut self) {
        let x0 = (self.cam_x as i32) / 16 - 1;
        let x1 = ((self.cam_x + 256.0) as i32) / 16 + 1;
        let y0 = (self.cam_y as i32) / 16 - 1;
        let y1 = ((self.cam_y + 256.0) as i32) / 16 + 1;
        let mx = self.sprites[MARIO].x;
        for tx in x0..=x1 {
            for ty in y0..=y1 {
                let centre = (16 * tx + 8) as f32;
                let mut dir = 0;
                if centre > mx + 16.0 {
                    dir = -1;
                }
                if centre < mx - 16.0 {
                    dir = 1;
                }
                let template = self.level.template(tx, ty);
                if template != 0 {
                    let code = Some((tx, ty, template));
                    let li = ty as usize * self.level.width + tx as usize;
                    let present = self.list.iter().any(|&id| self.sprites[id].origin == code);
                    if !present && self.last_seen[li] != self.tick_count - 1 {
                        let id = if template == kind::FLOWER {
                            self.new_flower((16 * tx + 17) as f32, (16 * ty + 18) as f32)
                        } else {
                            self.new_enemy(template, (16 * tx + 8) as f32, (16 * ty + 15) as f32, dir)
                        };
                        self.sprites[id].origin = code;
                        self.add(id);
                    }
                    self.last_seen[li] = self.tick_count;
                }
                if dir != 0 && level::has(self.level.tile(tx, ty), level::CANNON) && self.tick_count % 100 == 0 {
                    let mut b = Sprite::new(
                        kind::BULLET_BILL,
                        (16 * tx + 8 + 8 * dir) as f32,
                        (16 * ty + 15) as f32,
                        4,
                        12,
                    );
                    b.ya = -5.0;
                    b.facing = dir;
                    let id = self.push(b);
                    self.add(id);
                }
            }
        }
    }

    fn push(&mut self, s: Sprite) -> usize {
        self.sprites.push(s);
        self.sprites.len() - 1
    }

    fn new_enemy(&mut self, kind: i32, x: f32, y: f32, dir: i32) -> usize {
        let h = if (kind::RED_KOOPA..=kind::GREEN_KOOPA_WINGED).contains(&kind) {
            24
        } else {
            12
        };
        let mut s = Sprite::new(kind, x, y, 4, h);
        s.facing = if dir == 0 { 1 } else { dir };
        s.winged = kind % 2 == 1;
        self.push(s)
    }

    fn new_flower(&mut self, x: f32, y: f32) -> usize {
        let mut s = Sprite::new(kind::FLOWER, x, y, 2, 12);
        s.facing = 1; // never used by the logic; the traces show +1
        s.y_start = y;
        s.ya = -1.0;
        s.y -= 1.0;
        let id = self.push(s);
        for _ in 0..4 {
            self.update_flower(id);
        }
        id
    }

    /// Adds a sprite created during the tick: pending insertion, one immediate update (§4.5).
    fn add(&mut self, id: usize) {
        self.added.push(id);
        self.sprites[id].alive = true;
        self.update(id);
    }

    /// Deferred removal (§4.6).
    fn remove(&mut self, id: usize) {
        self.sprites[id].alive = false;
        self.removed.push(id);
    }

    // ------------------------------------------------------------------ movement (§6)

    /// Moves sprite `id` by (dx, dy) with collision; true if it moved.
    fn move_by(&mut self, id: usize, dx: f32, dy: f32) -> bool {
        self.substeps = 0;
        self.move_inner(id, dx, dy)
    }

    fn move_inner(&mut self, id: usize, mut dx: f32, mut dy: f32) -> bool {
        while dx > 8.0 {
            if !self.sub_step(id, 8.0, 0.0) {
                return false;
            }
            dx -= 8.0;
        }
        while dx < -8.0 {
            if !self.sub_step(id, -8.0, 0.0) {
                return false;
            }
            dx += 8.0;
        }
        while dy > 8.0 {
            if !self.sub_step(id, 0.0, 8.0) {
                return false;
            }
            dy -= 8.0;
        }
        while dy < -8.0 {
            if !self.sub_step(id, 0.0, -8.0) {
                return false;
            }
            dy += 8.0;
        }
        self.move_probe(id, dx, dy)
    }

    fn sub_step(&mut self, id: usize, dx: f32, dy: f32) -> bool {
        self.substeps += 1;
        if self.substeps > MAX_SUBSTEPS {
            return false;
        }
        self.move_probe(id, dx, dy)
    }

    fn move_probe(&mut self, id: usize, dx: f32, dy: f32) -> bool {
        let s = &self.sprites[id];
        let (x, y, w, h) = (s.x, s.y, s.w as f32, s.h as f32);
        let h2 = (s.h / 2) as f32;
        let mut collide = false;
        if dy > 0.0 {
            collide = self.probe(id, x + dx - w, y + dy, dx, 0.0)
                || self.probe(id, x + dx + w, y + dy, dx, 0.0)
                || self.probe(id, x + dx - w, y + dy + 1.0, dx, dy)
                || self.probe(id, x + dx + w, y + dy + 1.0, dx, dy);
        }
        if dy < 0.0 {
            collide = self.probe(id, x + dx, y + dy - h, dx, dy)
                || self.probe(id, x + dx - w, y + dy - h, dx, dy)
                || self.probe(id, x + dx + w, y + dy - h, dx, dy);
        }
        let red = {
            let k = self.sprites[id].kind;
            k == kind::RED_KOOPA || k == kind::RED_KOOPA_WINGED
        };
        if dx > 0.0 {
            let a = self.probe(id, x + dx + w, y + dy - h, dx, dy);
            let b = self.probe(id, x + dx + w, y + dy - h2, dx, dy);
            let c = self.probe(id, x + dx + w, y + dy, dx, dy);
            collide |= a | b | c;
            if red
                && self.sprites[id].on_ground
                && !self
                    .level
                    .blocks(((x + dx + w) / 16.0) as i32, (y / 16.0 + 1.0) as i32, dx, 1.0)
            {
                collide = true;
            }
        }
        if dx < 0.0 {
            let a = self.probe(id, x + dx - w, y + dy - h, dx, dy);
            let b = self.probe(id, x + dx - w, y + dy - h2, dx, dy);
            let c = self.probe(id, x + dx - w, y + dy, dx, dy);
            collide |= a | b | c;
            if red
                && self.sprites[id].on_ground
                && !self
                    .level
                    .blocks(((x + dx - w) / 16.0) as i32, (y / 16.0 + 1.0) as i32, dx, 1.0)
            {
                collide = true;
            }
        }
        if collide {
            let is_mario = id == MARIO;
            let s = &mut self.sprites[id];
            let (x, y) = (s.x, s.y);
            if dx < 0.0 {
                s.x = ((((x - w) / 16.0) as i32) * 16 + s.w) as f32;
                s.xa = 0.0;
            }
            if dx > 0.0 {
                s.x = ((((x + w) / 16.0 + 1.0) as i32) * 16 - s.w - 1) as f32;
                s.xa = 0.0;
            }
            if dy < 0.0 {
                s.y = ((((y - h) / 16.0) as i32) * 16 + s.h) as f32;
                s.ya = 0.0;
                if is_mario {
                    self.mario.jump_time = 0;
                }
            }
            if dy > 0.0 {
                let s = &mut self.sprites[id];
                s.y = if is_mario {
                    ((((y - 1.0) / 16.0 + 1.0) as i32) * 16 - 1) as f32
                } else {
                    (((y / 16.0 + 1.0) as i32) * 16 - 1) as f32
                };
                s.on_ground = true;
            }
            false
        } else {
            let s = &mut self.sprites[id];
            s.x += dx;
            s.y += dy;
            true
        }
    }

    /// The probe of sprite `id` at pixel (px, py) for motion (bx, by) (§6.1–6.3).
    fn probe(&mut self, id: usize, px: f32, py: f32, bx: f32, by: f32) -> bool {
        let (tx, ty) = ((px / 16.0) as i32, (py / 16.0) as i32);
        let s = &self.sprites[id];
        if tx == (s.x / 16.0) as i32 && ty == (s.y / 16.0) as i32 {
            return false;
        }
        let kind = s.kind;
        let b = self.level.blocks(tx, ty, bx, by);
        if id == MARIO {
            if level::has(self.level.tile(tx, ty), level::PICKABLE) {
                self.event(event::COLLECT, 15);
                self.collect_coin();
                self.level.set_tile(tx, ty, 0);
            }
            if b && by < 0.0 {
                let large = self.mario.is_large;
                self.bump(tx, ty, large);
            }
        } else if kind == kind::SHELL && b && by == 0.0 && bx != 0.0 {
            self.bump(tx, ty, true);
        }
        b
    }

    // ------------------------------------------------------------------ blocks (§9)

    fn bump(&mut self, tx: i32, ty: i32, may_break: bool) {
        let t = self.level.tile(tx, ty);
        if level::has(t, level::BUMPABLE) {
            self.bump_above(tx, ty - 1);
            self.event(event::BUMP, 24);
            self.level.set_tile(tx, ty, 14);
            let (x, y) = ((16 * tx + 9) as f32, (16 * ty + 8) as f32);
            if level::has(t, level::POWERUP) {
                let k = if self.mario.is_large {
                    kind::FIRE_FLOWER
                } else {
                    kind::MUSHROOM
                };
                let mut s = Sprite::new(k, x, y, 4, 12);
                s.facing = 1;
                let id = self.push(s);
                self.add(id);
            } else if level::has(t, level::LIFE) {
                let mut s = Sprite::new(kind::LIFE_MUSHROOM, x, y, 4, 12);
                s.facing = 1;
                let id = self.push(s);
                self.add(id);
            } else {
                self.collect_coin();
            }
        } else if level::has(t, level::BREAKABLE) {
            self.bump_above(tx, ty - 1);
            if may_break {
                self.event(event::BUMP, 22);
                self.level.set_tile(tx, ty, 0);
            }
        }
    }

    fn bump_above(&mut self, tx: i32, ty: i32) {
        if level::has(self.level.tile(tx, ty), level::PICKABLE) {
            self.event(event::COLLECT, 15);
            self.collect_coin();
            self.level.set_tile(tx, ty, 0);
        }
        let mario_facing = self.sprites[MARIO].facing;
        let (left, right) = ((16 * tx) as f32, (16 * tx + 16) as f32);
        for i in 0..self.list.len() {
            let id = self.list[i];
            let s = &self.sprites[id];
            if !s.alive {
                continue;
            }
            let bumpable = s.is_walker()
                || matches!(
                    s.kind,
                    kind::FLOWER | kind::MUSHROOM | kind::LIFE_MUSHROOM | kind::SHELL
                );
            let w = s.w as f32;
            if bumpable && s.x + w > left && s.x - w < right && ty == ((s.y - 1.0) / 16.0) as i32 {
                if s.is_enemy() {
                    self.remove(id);
                } else {
                    let s = &mut self.sprites[id];
                    s.facing = -mario_facing;
                    s.ya = -10.0;
                }
            }
        }
    }

    // ------------------------------------------------------------------ Mario's fortunes (§7.3)

    fn mario_alive(&self) -> bool {
        self.sprites[MARIO].alive
    }

    fn collect_coin(&mut self) {
        if !self.mario_alive() {
            return;
        }
        self.coins += 1;
        if self.coins % 100 == 0 {
            self.lives += 1;
        }
    }

    fn lose(&mut self) {
        self.event(event::LOSE, 0);
        self.status = Status::Lose;
        self.sprites[MARIO].alive = false;
    }

    fn hurt(&mut self) {
        if self.mario.invulnerable > 0 || !self.mario_alive() {
            return;
        }
        if self.mario.is_large {
            self.pause = 9;
            if self.mario.is_fire {
                self.mario.is_fire = false;
            } else {
                self.mario.is_large = false;
            }
            self.mario.invulnerable = 32;
        } else {
            self.lose();
        }
    }

    fn mushroom(&mut self) {
        if !self.mario_alive() {
            return;
        }
        if !self.mario.is_large {
            self.pause = 9;
            self.mario.is_large = true;
        } else {
            self.collect_coin();
        }
    }

    fn flower(&mut self) {
        if !self.mario_alive() {
            return;
        }
        if !self.mario.is_fire {
            self.pause = 9;
            self.mario.is_fire = true;
            self.mario.is_large = true;
        } else {
            self.collect_coin();
        }
    }

    fn stomp_bounce(&mut self, target: usize) {
        if !self.mario_alive() {
            return;
        }
        let t = &self.sprites[target];
        let dy = (t.y - (t.h / 2) as f32) - self.sprites[MARIO].y;
        self.move_by(MARIO, 0.0, dy);
        self.mario.jump_time = 8;
        let m = &mut self.sprites[MARIO];
        m.ya = 8.0 * -1.9;
        m.on_ground = false;
        self.mario.invulnerable = 1;
    }

    fn is_stomp(&self, target: usize) -> bool {
        let m = &self.sprites[MARIO];
        let dy = m.y - self.sprites[target].y;
        m.ya > 0.0 && dy <= 0.0 && (!m.on_ground || !self.mario.was_on_ground)
    }

    // ------------------------------------------------------------------ updates (§7, §8)

    fn update(&mut self, id: usize) {
        match self.sprites[id].kind {
            kind::MARIO => self.update_mario(),
            k if (kind::GOOMBA..=kind::SPIKY_WINGED).contains(&k) => self.update_walker(id),
            kind::BULLET_BILL => {
                let s = &mut self.sprites[id];
                s.xa = s.facing as f32 * 4.0;
                s.x += s.xa;
            }
            kind::FLOWER => self.update_flower(id),
            kind::MUSHROOM | kind::LIFE_MUSHROOM => {
                let s = &mut self.sprites[id];
                if s.life < 9 {
                    s.y -= 1.0;
                    s.life += 1;
                } else {
                    self.update_walker(id);
                }
            }
            kind::FIRE_FLOWER => {
                let s = &mut self.sprites[id];
                s.life += 1;
                if s.life < 9 {
                    s.y -= 1.0;
                }
            }
            kind::SHELL => self.update_shell(id),
            kind::FIREBALL => self.update_fireball(id),
            _ => {}
        }
    }

    fn update_walker(&mut self, id: usize) {
        let s = &mut self.sprites[id];
        if s.xa > 2.0 {
            s.facing = 1;
        }
        if s.xa < -2.0 {
            s.facing = -1;
        }
        s.xa = s.facing as f32 * 1.75;
        let xa = s.xa;
        if !self.move_by(id, xa, 0.0) {
            let s = &mut self.sprites[id];
            s.facing = -s.facing;
        }
        self.sprites[id].on_ground = false;
        let ya = self.sprites[id].ya;
        self.move_by(id, 0.0, ya);
        let s = &mut self.sprites[id];
        s.ya *= if s.winged { 0.95 } else { 0.85 };
        s.xa *= 0.89;
        if !s.on_ground {
            s.ya += if s.winged { 0.6 } else { 2.0 };
        } else if s.winged {
            s.ya = -10.0;
        }
    }

    fn update_flower(&mut self, id: usize) {
        let mx = self.sprites[MARIO].x;
        let s = &mut self.sprites[id];
        if s.ya > 0.0 {
            if s.y >= s.y_start {
                s.y = s.y_start;
                let d = (mx - s.x).abs() as i32;
                s.wait += 1;
                if s.wait > 40 && d > 24 {
                    s.wait = 0;
                    s.ya = -1.0;
                }
            }
        } else if s.ya < 0.0 && s.y_start - s.y > 20.0 {
            s.y = s.y_start - 20.0;
            s.wait += 1;
            if s.wait > 40 {
                s.wait = 0;
                s.ya = 1.0;
            }
        }
        s.y += s.ya;
    }

    fn update_shell(&mut self, id: usize) {
        let s = &mut self.sprites[id];
        if s.xa > 2.0 {
            s.facing = 1;
        }
        if s.xa < -2.0 {
            s.facing = -1;
        }
        s.xa = s.facing as f32 * 11.0;
        let xa = s.xa;
        if s.facing != 0 {
            self.shell_checks.push(id);
        }
        if !self.move_by(id, xa, 0.0) {
            let s = &mut self.sprites[id];
            s.facing = -s.facing;
        }
        self.sprites[id].on_ground = false;
        let ya = self.sprites[id].ya;
        self.move_by(id, 0.0, ya);
        let s = &mut self.sprites[id];
        s.ya *= 0.85;
        s.xa *= 0.89;
        if !s.on_ground {
            s.ya += 2.0;
        }
    }

    fn update_fireball(&mut self, id: usize) {
        let s = &mut self.sprites[id];
        if s.xa > 2.0 {
            s.facing = 1;
        }
        if s.xa < -2.0 {
            s.facing = -1;
        }
        s.xa = s.facing as f32 * 8.0;
        let xa = s.xa;
        self.fireball_checks.push(id);
        if !self.move_by(id, xa, 0.0) {
            self.remove(id);
            return;
        }
        self.sprites[id].on_ground = false;
        let ya = self.sprites[id].ya;
        self.move_by(id, 0.0, ya);
        let s = &mut self.sprites[id];
        if s.on_ground {
            s.ya = -10.0;
        }
        s.ya *= 0.95;
        s.xa *= 0.89;
        if !s.on_ground {
            s.ya = (f64::from(s.ya) + 1.5) as f32;
        }
    }

    fn update_mario(&mut self) {
        let b = self.mario.buttons;
        if self.mario.invulnerable > 0 {
            self.mario.invulnerable -= 1;
        }
        self.mario.was_on_ground = self.sprites[MARIO].on_ground;
        let push: f32 = if b.speed { 1.2 } else { 0.6 };
        if self.sprites[MARIO].on_ground {
            self.mario.is_ducking = b.down && self.mario.is_large;
        }
        self.sprites[MARIO].h = if self.mario.is_large {
            if self.mario.is_ducking { 12 } else { 24 }
        } else {
            12
        };
        {
            let m = &mut self.sprites[MARIO];
            if m.xa > 2.0 {
                m.facing = 1;
            }
            if m.xa < -2.0 {
                m.facing = -1;
            }
        }
        if b.jump {
            if self.sprites[MARIO].on_ground && self.mario.may_jump {
                self.mario.jump_time = 7;
                let m = &mut self.sprites[MARIO];
                m.ya = 7.0 * -1.9;
                m.on_ground = false;
                let (x, w) = (m.x, m.w as f32);
                let hy = (m.y - 4.0) - m.h as f32;
                let blocked = self.probe(MARIO, x, hy, 0.0, -4.0)
                    || self.probe(MARIO, x - w, hy, 0.0, -4.0)
                    || self.probe(MARIO, x + w, hy, 0.0, -4.0);
                if !blocked {
                    self.mario.x_jump_start = self.sprites[MARIO].x;
                    self.event(event::JUMP, 0);
                }
            } else if self.mario.jump_time > 0 {
                let m = &mut self.sprites[MARIO];
                m.xa += 0.0;
                m.ya = self.mario.jump_time as f32 * -1.9;
                self.mario.jump_time -= 1;
            }
        } else {
            self.mario.jump_time = 0;
        }
        let ducking = self.mario.is_ducking;
        {
            let m = &mut self.sprites[MARIO];
            if b.left && !ducking {
                m.xa -= push;
                m.facing = -1;
            }
            if b.right && !ducking {
                m.xa += push;
                m.facing = 1;
            }
        }
        if b.speed && self.mario.can_shoot && self.mario.is_fire && self.fireballs_on_screen < 2 {
            let m = &self.sprites[MARIO];
            let mut f = Sprite::new(kind::FIREBALL, m.x + (6 * m.facing) as f32, m.y - 20.0, 4, 8);
            f.facing = m.facing;
            f.ya = 4.0;
            let id = self.push(f);
            self.add(id);
        }
        self.mario.can_shoot = !b.speed;
        self.mario.may_jump = self.sprites[MARIO].on_ground && !b.jump;
        {
            let m = &mut self.sprites[MARIO];
            if m.xa.abs() < 0.5 {
                m.xa = 0.0;
            }
            m.on_ground = false;
        }
        let xa = self.sprites[MARIO].xa;
        self.move_by(MARIO, xa, 0.0);
        let ya = self.sprites[MARIO].ya;
        self.move_by(MARIO, 0.0, ya);
        if !self.mario.was_on_ground && self.sprites[MARIO].on_ground && self.mario.x_jump_start >= 0.0 {
            self.event(event::LAND, 0);
            self.mario.x_jump_start = -100.0;
        }
        let exit_px = (16 * self.level.exit.0) as f32;
        {
            let m = &mut self.sprites[MARIO];
            if m.x < 0.0 {
                m.x = 0.0;
                m.xa = 0.0;
            }
        }
        if self.sprites[MARIO].x > exit_px {
            let m = &mut self.sprites[MARIO];
            m.x = exit_px;
            m.xa = 0.0;
            self.event(event::WIN, 0);
            self.status = Status::Win;
        }
        let k = self.mario.inertia;
        let m = &mut self.sprites[MARIO];
        m.ya *= 0.85;
        m.xa *= k;
        if !m.on_ground {
            m.ya += 3.0;
        }
    }

    // ------------------------------------------------------------------ contacts (§8)

    fn in_box(&self, id: usize, half: f32) -> bool {
        let (m, s) = (&self.sprites[MARIO], &self.sprites[id]);
        let (dx, dy) = (m.x - s.x, m.y - s.y);
        dx > -half && dx < half && dy > -(s.h as f32) && dy < m.h as f32
    }

    fn contact(&mut self, id: usize) {
        let k = self.sprites[id].kind;
        match k {
            kind::MARIO => {}
            _ if self.sprites[id].is_walker() || k == kind::FLOWER => {
                let w = self.sprites[id].w;
                if !self.in_box(id, (2 * w + 4) as f32) {
                    return;
                }
                if k != kind::FLOWER && !self.sprites[id].is_spiky() && self.is_stomp(id) {
                    self.stomp_bounce(id);
                    if self.sprites[id].winged {
                        let s = &mut self.sprites[id];
                        s.winged = false;
                        s.ya = 0.0;
                    } else {
                        if (kind::RED_KOOPA..=kind::GREEN_KOOPA_WINGED).contains(&k) {
                            let s = &self.sprites[id];
                            let mut shell = Sprite::new(kind::SHELL, s.x, s.y, 4, 12);
                            shell.ya = -5.0;
                            shell.origin = s.origin;
                            let sid = self.push(shell);
                            self.add(sid);
                        }
                        self.event(event::STOMP_KILL, k);
                        self.remove(id);
                    }
                } else {
                    self.event(event::HURT, k);
                    self.hurt();
                }
            }
            kind::BULLET_BILL => {
                if !self.in_box(id, 16.0) {
                    return;
                }
                if self.is_stomp(id) {
                    self.stomp_bounce(id);
                    self.remove(id);
                } else {
                    self.event(event::HURT, k);
                    self.hurt();
                }
            }
            kind::MUSHROOM | kind::LIFE_MUSHROOM | kind::FIRE_FLOWER => {
                if !self.in_box(id, 16.0) {
                    return;
                }
                self.event(event::COLLECT, k);
                match k {
                    kind::MUSHROOM => self.mushroom(),
                    kind::FIRE_FLOWER => self.flower(),
                    _ => self.lives += i32::from(self.mario_alive()),
                }
                self.remove(id);
            }
            kind::SHELL => {
                if !self.in_box(id, 16.0) {
                    return;
                }
                let mario_facing = self.sprites[MARIO].facing;
                if self.is_stomp(id) {
                    self.stomp_bounce(id);
                    let s = &mut self.sprites[id];
                    if s.facing != 0 {
                        s.xa = 0.0;
                        s.facing = 0;
                    } else {
                        s.facing = mario_facing;
                    }
                } else if self.sprites[id].facing != 0 {
                    self.event(event::HURT, k);
                    self.hurt();
                } else {
                    self.event(event::KICK, k);
                    if self.mario_alive() {
                        self.mario.invulnerable = 1;
                    }
                    self.sprites[id].facing = mario_facing;
                }
            }
            _ => {}
        }
    }

    /// Whether moving shell `shell` kills sprite `s` (§8.2, 8.3, 8.7); records the event.
    fn shell_rule(&mut self, s: usize, shell: usize) -> bool {
        let (m, t) = (&self.sprites[shell], &self.sprites[s]);
        let k = t.kind;
        if !(t.is_enemy() || k == kind::SHELL) {
            return false;
        }
        let (dx, dy) = (m.x - t.x, m.y - t.y);
        if !(dx > -16.0 && dx < 16.0 && dy > -(t.h as f32) && dy < m.h as f32) {
            return false;
        }
        self.event(event::SHELL_KILL, k);
        if k == kind::SHELL {
            self.remove(shell);
        }
        true
    }

    /// Whether fireball `fb` hits sprite `s` (§8.2, 8.3, 8.8); kills it where the rule says so.
    fn fireball_rule(&mut self, s: usize, fb: usize) -> bool {
        let (f, t) = (&self.sprites[fb], &self.sprites[s]);
        let k = t.kind;
        if !(t.is_enemy() || k == kind::SHELL) {
            return false;
        }
        let (dx, dy) = (f.x - t.x, f.y - t.y);
        if dx <= -16.0 || dx >= 16.0 || dy <= -(t.h as f32) || dy >= f.h as f32 {
            return false;
        }
        match k {
            kind::BULLET_BILL => {}
            kind::SHELL => {
                if t.facing == 0 {
                    self.remove(s);
                }
            }
            _ if t.is_spiky() => {}
            _ => {
                self.event(event::FIRE_KILL, k);
                self.remove(s);
            }
        }
        true
    }
}
