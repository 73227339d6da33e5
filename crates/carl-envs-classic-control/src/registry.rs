//! The classic-control family's registrations.

use carl_env::registration::{AuditProfile, Registration, StepCost, VectorKernel, params};
use carl_env::runtime::AnyEnv;

use crate::{
    Acrobot, AcrobotParams, CartPole, CartPoleParams, MountainCar, MountainCarContinuous, MountainCarContinuousParams,
    MountainCarParams, Pendulum, PendulumParams,
};

const PI: f64 = std::f64::consts::PI;

/// The environments of this family, in registry order.
pub const REGISTRATIONS: &[Registration] = &[
    Registration {
        id: "cartpole",
        build: |v, _| {
            Ok(AnyEnv::new(CartPole::new(params::<CartPoleParams>(
                "cartpole",
                v,
                CartPoleParams::set,
            )?)))
        },
        runtime_default: |n| CartPoleParams::default().get(n).ok(),
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile::STANDARD,
        vector_kernel: Some(VectorKernel::CartPole),
    },
    Registration {
        id: "pendulum",
        build: |v, _| {
            Ok(AnyEnv::new(Pendulum::new(params::<PendulumParams>(
                "pendulum",
                v,
                PendulumParams::set,
            )?)))
        },
        runtime_default: |n| PendulumParams::default().get(n).ok(),
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile {
            state_hint: &[(-PI, PI), (-8.0, 8.0)],
            ..AuditProfile::STANDARD
        },
        vector_kernel: None,
    },
    Registration {
        id: "mountain_car",
        build: |v, _| {
            let p = params::<MountainCarParams>("mountain_car", v, MountainCarParams::set)?;
            Ok(AnyEnv::new(MountainCar::new(p)))
        },
        runtime_default: |n| MountainCarParams::default().get(n).ok(),
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile::STANDARD,
        vector_kernel: None,
    },
    Registration {
        id: "mountain_car_continuous",
        build: |v, _| {
            let p =
                params::<MountainCarContinuousParams>("mountain_car_continuous", v, MountainCarContinuousParams::set)?;
            Ok(AnyEnv::new(MountainCarContinuous::new(p)))
        },
        runtime_default: |n| MountainCarContinuousParams::default().get(n).ok(),
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile::STANDARD,
        vector_kernel: None,
    },
    Registration {
        id: "acrobot",
        build: |v, _| {
            Ok(AnyEnv::new(Acrobot::new(params::<AcrobotParams>(
                "acrobot",
                v,
                AcrobotParams::set,
            )?)))
        },
        runtime_default: |n| AcrobotParams::default().get(n).ok(),
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile {
            state_hint: &[(-PI, PI), (-PI, PI), (-4.0 * PI, 4.0 * PI), (-9.0 * PI, 9.0 * PI)],
            ..AuditProfile::STANDARD
        },
        vector_kernel: None,
    },
];
