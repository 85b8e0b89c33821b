//! Why a plate that shows contacts gave no gait event: said, never left silent. A plate
//! event needs one foot alone on the plate, told by the centre of pressure lying under that
//! foot's heel–toe line ([`gait::plates`]); a contact that no foot explains is dropped
//! there. This says which plates lost all their contacts so, and the likeliest reason the
//! data show: a centre of pressure outside the plate itself (its FORCE_PLATFORM:ORIGIN read
//! with the opposite sign is the common cause, as on `c3d-labs`' instrumented treadmill),
//! or feet that are not over it.

use crate::platforms::{force_platforms, off_plate, ForceOptions};
use gait::PlateOptions;

/// One sentence per plate that has contacts (as the plate detector counts them) but none
/// of whose contacts gave an event in `events`.
pub fn silent_plates(
    c: &c3d::C3d,
    events: &[gait::Event],
    opts: &PlateOptions,
) -> crate::Result<Vec<String>> {
    let fp = force_platforms(c, &ForceOptions::default())?;
    let mm = c3d::mm_per_unit(&c.point_units());
    let rate = c.analog_rate() as f64;
    let mut out = Vec::new();
    for p in &fp.platforms {
        if events.iter().any(|e| e.plate == Some(p.index)) {
            continue;
        }
        let push: Vec<f64> = p.push.iter().map(|v| v.max(0.0)).collect();
        let min = (opts.min_contact_s * rate).ceil() as usize;
        let contacts: Vec<[usize; 2]> = kinetics::contacts(&push, opts.threshold_n, rate)
            .into_iter()
            .filter(|[a, b]| b + 1 - a >= min)
            .collect();
        if contacts.is_empty() {
            continue;
        }
        let outside = contacts
            .iter()
            .filter(|[a, b]| {
                let mid = (a + b) / 2;
                p.cop
                    .get(mid)
                    .is_some_and(|cop| off_plate(&p.corners, cop, mm))
            })
            .count();
        out.push(if outside * 2 > contacts.len() {
            format!(
                "plate {}: {} contact(s) but no event: the centre of pressure lies outside the plate in {outside} of them (FORCE_PLATFORM:ORIGIN's x and y may be written with the opposite sign), so no foot can be told",
                p.index,
                contacts.len()
            )
        } else {
            format!(
                "plate {}: {} contact(s) but no event: in none does one foot alone stand over the centre of pressure (within {} mm of its heel–toe line, the other foot clearly farther)",
                p.index,
                contacts.len(),
                opts.max_foot_distance_mm
            )
        });
    }
    Ok(out)
}
