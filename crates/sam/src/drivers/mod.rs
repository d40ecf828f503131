//! What the front ends run: one contact ([`one_contact`]: normal load, then an optional tangential
//! increment, with or without inhomogeneities), the fretting loop ([`fretting_loop`]: a load path
//! with an observer, snapshots and metrics) and the fretting map ([`fretting_map`]: the loop per
//! point of loads × amplitudes) and fretting wear over cycles ([`fretting_wear3d`]).

pub mod fretting_loop;
pub mod fretting_map;
pub mod fretting_wear3d;
pub mod one_contact;
