//! The kinematic methods' vocabulary: which methods there are, their constants, and what
//! every method shares for one trial. Its own module so that the method files
//! ([`crate::oconnor`], [`crate::desailly`], …) and the dispatcher that runs them
//! ([`crate::kinematic`]) each import it, and not each other.

use crate::axes::Vertical;
use crate::error::{Error, Result};

/// A kinematic method for one kind of event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Zeni 2008 as published: the heel's forward extreme (strike) and the toe's backward
    /// extreme (off) relative to the pelvis.
    Zeni,
    /// Zeni's strike moved to the landing seen in the heel's and toe's heights
    /// ([`refine_strike`](crate::kinematic::refine_strike), [`KinematicOptions::touch_mm`]); for offs, Zeni's.
    ZeniLanding,
    /// The foot centre's vertical velocity (O'Connor 2007, [`crate::oconnor`]).
    OConnor,
    /// High-pass filtered forward heel and toe positions (Desailly 2009,
    /// [`crate::desailly`]).
    Desailly,
    /// Zeni's offs moved to where the toe starts to rise from its stance level
    /// ([`refine_off`](crate::kinematic::refine_off), [`KinematicOptions::lift_mm`]); for strikes, Zeni's landing
    /// ([`Method::ZeniLanding`]).
    ZeniLift,
    /// Zeni's events refined to where the heel or toe stops (strike) and the toe starts
    /// (off) moving, by speed thresholds scaled to the walking speed (Bonci et al. 2022,
    /// [`crate::velocity`]).
    Velocity,
    /// Strikes at the peak of the heel's upward acceleration near Zeni's strike, where the
    /// landing stops its descent ([`crate::impact`]); for offs, Zeni's.
    Impact,
    /// Strikes where the heel or toe has come down to a fraction of its swing height above
    /// its stance level (and the foot slowed to a fraction of its swing speed), offs where
    /// the toe leaves it by a fraction ([`crate::landing`]), each near Zeni's.
    Landing,
    /// Strikes where the heel or toe has come down to within a few millimetres of its
    /// stance level and stopped descending, offs where the toe has left its level by a few
    /// millimetres and moves forward ([`crate::touchdown`]), each near Zeni's.
    Touchdown,
}

impl std::str::FromStr for Method {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "zeni" => Ok(Method::Zeni),
            "zeni-landing" | "zenilanding" => Ok(Method::ZeniLanding),
            "oconnor" | "o'connor" => Ok(Method::OConnor),
            "desailly" => Ok(Method::Desailly),
            "velocity" => Ok(Method::Velocity),
            "zeni-lift" | "zenilift" => Ok(Method::ZeniLift),
            "impact" => Ok(Method::Impact),
            "landing" => Ok(Method::Landing),
            "touchdown" => Ok(Method::Touchdown),
            _ => Err(Error::Input(format!(
                "method {s}: expected zeni, zeni-landing, zeni-lift, oconnor, desailly, velocity, impact, landing or touchdown"
            ))),
        }
    }
}

/// One method's estimate of an event kind and its mean lead or lag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub method: Method,
    /// Added to the method's instants (s): its median signed error against the tuning
    /// labs' plates and events (c3d-samples; `events_eval --dump`, docs/events.md).
    pub offset_s: f64,
}

/// The methods' constants.
#[derive(Debug, Clone, PartialEq)]
pub struct KinematicOptions {
    /// How foot strikes are found: the first estimate decides which strikes exist; each
    /// strike's time is the mean of the estimates (offsets added) that have an event of
    /// that foot within [`KinematicOptions::combine_window_s`] of it. Averaging methods
    /// whose errors differ (an extreme of position, a landing in height, a filtered turn)
    /// cancels part of each one's lab-to-lab drift: on the tuning labs the mean of three
    /// kept the median |error| at 14 ms against 22 for the best one alone, the 95th
    /// percentile at 68 against 72 ms.
    pub strike: Vec<Estimate>,
    /// How foot offs are found, likewise (Zeni's alone: no combination gained on the
    /// tuning labs' 95th percentile).
    pub off: Vec<Estimate>,
    /// How foot offs are found on a run ([`crate::running`]; empty: as [`KinematicOptions::off`]
    /// on every trial). The trial is a run when the offs of [`KinematicOptions::off`],
    /// against the strikes, show flight phases. The toe leaving its stance level
    /// ([`Method::ZeniLift`]) came 5 ms before the plates' and the lab's offs on c3d-more's
    /// run (JA1Gait35), which its offset undoes; the runs of c3d-labs are reported
    /// (docs/events.md, "Running").
    pub running_off: Vec<Estimate>,
    /// Half the window (s) within which the other estimates' events join the first's: less
    /// than half the shortest stride, so only the same step's estimates join, and wide
    /// enough that one method going astray by 100 ms still counts as one vote of three
    /// (the tuning labs' 95th percentile was lowest with no narrower limit).
    pub combine_window_s: f64,
    /// O'Connor: low-pass cut-off (Hz) applied to the foot centre before it is
    /// differentiated (chosen on the tuning labs).
    pub oconnor_lowpass_hz: f64,
    /// Desailly: high-pass cut-off as a multiple of the trial's stride frequency (chosen on
    /// the tuning labs).
    pub desailly_cutoff_ratio: f64,
    /// Half the window (s) over which the pelvis' displacement gives the walking direction:
    /// about one step, so the side-to-side sway of each step cancels.
    pub direction_window_s: f64,
    /// Slowest pelvis speed taken as walking (mm/s).
    pub min_speed_mm_s: f64,
    /// Shortest time (s) between two strikes (or two offs) of one foot, halved: an
    /// extremum must be the largest within this distance either side.
    pub min_half_stride_s: f64,
    /// Width (s) of the moving average applied to Zeni's heel and toe signals (0 for none).
    pub smooth_s: f64,
    /// [`Method::ZeniLanding`]: how near (mm) its stance level a heel or toe must be for its
    /// descent's end to be the landing ([`refine_strike`](crate::kinematic::refine_strike)).
    pub touch_mm: f64,
    /// [`Method::ZeniLanding`] with an ankle marker standing in for the heel (its height says
    /// nothing of the landing): Zeni's instant plus this (s); the malleolus peaks forward
    /// about 20 ms before the landing on the tuning labs.
    pub ankle_strike_offset_s: f64,
    /// [`Method::ZeniLift`]: how far (mm) above its stance level the toe must rise for the
    /// foot to be off ([`refine_off`](crate::kinematic::refine_off)).
    pub lift_mm: f64,
    /// [`Method::Velocity`]: the heel has landed when its 3-D speed falls below this
    /// fraction of the walking speed (Bonci et al. 2022: 0.5).
    pub velocity_heel_ratio: f64,
    /// [`Method::Velocity`]: the toe has landed when its speed falls below, and has left
    /// the floor when it rises through, this fraction of the walking speed (Bonci et al.
    /// 2022: 0.8).
    pub velocity_toe_ratio: f64,
    /// [`Method::Impact`]: low-pass cut-off (Hz) applied to the heel's height before it is
    /// differentiated twice.
    pub impact_lowpass_hz: f64,
    /// [`Method::Impact`]: how far after Zeni's strike (s) the impact is looked for.
    pub impact_after_s: f64,
    /// How far (s) the pelvis is carried at constant velocity before its first and after
    /// its last captured frame (the velocity of its first or last 0.1 s); 0 (none) by default. BTK's
    /// 561xxa01 sees the feet 0.5 s before the pelvis, and its first strike has no
    /// heel-to-pelvis extreme without it; 0.25 s finds it 3 ms from its plate, but that
    /// strike's lag differs from the trial's others by 20 ms and the calibration on the
    /// trial's plates gets worse held out (docs/events.md), so it is measured, not used.
    pub pelvis_extend_s: f64,
    /// Zeni's extremes next to a gap or the trial's edge: the side the cut comes within
    /// the prominence's reach must fall by at least this fraction of the full prominence
    /// over its known samples (two at least; the other side still needs all of it). The
    /// tuning labs' one such event (sample_03's last strike, its heel lost 20 ms after
    /// the lab's strike) is found with 0.05 or 0.1, not 0.2. At 1 or more, every side
    /// needs the full prominence, as before.
    pub cut_min_fall: f64,
    /// As [`Self::cut_min_fall`] where the trial's edge (not a gap) cuts the side: a fall
    /// above the marker's noise (0.02 of the prominence, 0.8 mm at the least prominence)
    /// shows the turn. BMC's one-cycle trial, cropped at its strikes, ends 20 ms after
    /// its last heel extreme, which falls 6 mm over those two frames.
    pub edge_min_fall: f64,
    /// Zeni's extremes just beyond the trial's ends (`signal::edge_maxima`):
    /// how far outside (s) the parabola through the first or last three samples may peak.
    /// An event is kept only where its estimate's offset brings it into the trial. 0:
    /// none.
    pub edge_beyond_s: f64,
    /// Zeni's heel and toe signals bridged over gaps this short (s) by a cubic
    /// (`signal::bridge_short`) before their extremes are looked for. 0: none.
    /// Chosen on c3d-labs (the tuning labs have no foot-marker gap near an event, so
    /// none of their figures moves at any value up to 0.2 s): MOtoNMS' right heels, lost
    /// for 83 ms (5 frames at 60 Hz) just before their strikes, need 0.1.
    pub bridge_s: f64,
    /// [`Method::Landing`]: a heel or toe has landed when it stands within this fraction
    /// of its swing height above its stance level.
    pub landing_height_frac: f64,
    /// [`Method::Landing`]: …and the heel's or toe's descent has slowed to this fraction
    /// of its fastest in terminal swing (0: not required)…
    pub landing_vspeed_frac: f64,
    /// [`Method::Landing`]: …and the foot centre's forward speed has fallen below this
    /// fraction of its swing's peak (0: not required).
    pub landing_speed_frac: f64,
    /// [`Method::Landing`]: the toe has left the floor when it rises above this fraction
    /// of its swing height over its stance level…
    pub lift_height_frac: f64,
    /// …or the foot centre's forward speed rises above this fraction of its swing's peak
    /// (0: not used).
    pub lift_speed_frac: f64,
    /// [`Method::Landing`]'s lift-off by speed reads the toe's forward speed instead of the
    /// foot centre's.
    pub lift_speed_of_toe: bool,
    /// Foot offs move by this many seconds per second that the foot's stride (its median
    /// interval between Zeni strikes) is longer than [`KinematicOptions::off_stride_ref_s`];
    /// the offs' own offset is their error at that stride. The toe's backward extreme
    /// relative to the pelvis is where the toe, rolling over before it leaves the floor,
    /// starts to catch up with the pelvis: the slower the walk, the earlier before the
    /// lift-off that comes. Fitted on the tuning labs' Zeni offs (Theil–Sen, plates and
    /// lab events pooled: error +24.2 ms − 12.4 ms per second of stride; docs/events.md),
    /// where it also held leaving each lab out of the fit. 0: a constant offset.
    pub off_stride_slope: f64,
    /// The stride (s) at which offs take their offset alone, and the stride assumed where a
    /// foot shows fewer than two strikes: the tuning labs' median (1.17 s).
    pub off_stride_ref_s: f64,
    /// [`Method::Touchdown`]'s strike: how far above its stance level (mm) the heel or toe
    /// may stand once landed.
    pub touchdown_mm: f64,
    /// [`Method::Touchdown`]'s strike: the vertical speed (mm/s) under which the part has
    /// stopped descending.
    pub touchdown_speed_mm_s: f64,
    /// [`Method::Touchdown`]: the low-pass cut-off (Hz) of the heights and the toe's
    /// forward position before they are differentiated.
    pub touchdown_lowpass_hz: f64,
    /// [`Method::Touchdown`]'s off: how far above its stance level (mm) the toe must rise.
    pub liftoff_mm: f64,
    /// [`Method::Touchdown`]'s off: the forward speed (mm/s) the toe must exceed.
    pub liftoff_speed_mm_s: f64,
}

impl Default for KinematicOptions {
    fn default() -> Self {
        let est = |method, offset_s| Estimate { method, offset_s };
        KinematicOptions {
            // Offsets: the tuning labs' median signed errors (plates and lab events
            // pooled), `events_eval --dump`.
            strike: vec![
                est(Method::ZeniLanding, -0.0012),
                est(Method::Zeni, 0.0225),
                est(Method::Desailly, 0.0210),
            ],
            // Zeni's off at the tuning labs' median stride; `off_stride_slope` for others.
            off: vec![est(Method::Zeni, -0.0098)],
            running_off: vec![est(Method::ZeniLift, 0.005)],
            combine_window_s: 0.2,
            oconnor_lowpass_hz: 10.0,
            desailly_cutoff_ratio: 0.3,
            direction_window_s: 0.5,
            min_speed_mm_s: 200.0,
            min_half_stride_s: 0.25,
            smooth_s: 0.0,
            touch_mm: 10.0,
            ankle_strike_offset_s: 0.02,
            lift_mm: 10.0,
            velocity_heel_ratio: 0.5,
            velocity_toe_ratio: 0.8,
            impact_lowpass_hz: 10.0,
            impact_after_s: 0.25,
            pelvis_extend_s: 0.0,
            cut_min_fall: 0.1,
            edge_min_fall: 0.02,
            edge_beyond_s: 0.03,
            bridge_s: 0.1,
            landing_height_frac: 0.1,
            landing_speed_frac: 0.0,
            landing_vspeed_frac: 0.0,
            lift_height_frac: 0.1,
            lift_speed_frac: 0.0,
            lift_speed_of_toe: false,
            off_stride_slope: 0.0124,
            off_stride_ref_s: 1.17,
            // Chosen on the tuning labs (docs/events.md, "A physically defined strike");
            // the method is measured, not in the defaults' estimates.
            touchdown_mm: 5.0,
            touchdown_speed_mm_s: 30.0,
            touchdown_lowpass_hz: 10.0,
            liftoff_mm: 2.0,
            liftoff_speed_mm_s: 1000.0,
        }
    }
}

/// What every method shares for one trial: the lab's vertical, the pelvis (short gaps
/// filled), the walking direction per frame and the search widths in frames.
pub struct Prepared {
    pub vertical: Vertical,
    pub pelvis: Vec<[f64; 3]>,
    pub dir: Vec<[f64; 3]>,
    /// The pelvis stays while the feet cycle: `dir` is the treadmill's
    /// ([`travel_direction`](crate::kinematic::travel_direction)).
    pub treadmill: bool,
    pub rate: f64,
    /// Frames either side within which an extremum must be the largest
    /// ([`KinematicOptions::min_half_stride_s`]).
    pub half: usize,
    /// Frames either side over which its prominence is measured.
    pub reach: usize,
}
