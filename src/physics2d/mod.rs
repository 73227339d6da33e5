//! A small 2-D rigid-body toolkit with Box2D 2.3's semantics (in `f64`), so that the Box2D
//! environments (BipedalWalker, LunarLander) can behave like Gymnasium's pybox2d ones. `distance`
//! computes closest points of convex shapes (GJK, Box2D's `b2Distance`); `toi` computes the time of
//! impact of two moving shapes (conservative advancement, Box2D's `b2TimeOfImpact`), which the
//! solver's continuous-collision pass uses to stop fast bodies at first contact instead of letting
//! them tunnel. Algorithms after Erin Catto's GDC talks and Box2D (zlib licence), reimplemented.

pub mod distance;
pub mod toi;
