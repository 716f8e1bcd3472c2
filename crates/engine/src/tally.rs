//! Running totals the pipeline keeps as it goes: amounts of particles and volume, and the
//! statistics of the nozzle's path.

/// A number of particles and the material volume they carry.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Amount {
    /// How many particles.
    pub count: u64,
    /// Volume, m³.
    pub volume: f64,
}

impl Amount {
    /// Adds one particle of `volume` (m³).
    #[inline]
    pub fn add(&mut self, volume: f64) {
        self.count += 1;
        self.volume += volume;
    }
}

impl std::ops::Add for Amount {
    type Output = Amount;
    fn add(self, o: Amount) -> Amount {
        Amount { count: self.count + o.count, volume: self.volume + o.volume }
    }
}

impl std::iter::Sum for Amount {
    fn sum<I: Iterator<Item = Amount>>(iter: I) -> Amount {
        iter.fold(Amount::default(), |a, b| a + b)
    }
}

/// Running totals over the whole run.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    /// Particles emitted.
    pub emitted: Amount,
    /// Particles that left the domain box.
    pub left_domain: Amount,
    /// Particles retired past the maximum lifetime.
    pub expired: Amount,
    /// Particles whose first substrate impact happened.
    pub substrate_first_impacts: Amount,
    /// Of those, the ones that rebounded from it.
    pub substrate_first_rebounds: Amount,
    /// Particles released by cohesive failures, drips and slumps.
    pub released: Amount,
    /// Released particles that left the domain.
    pub released_left: Amount,
    /// Released particles that expired.
    pub released_expired: Amount,
    /// Of the released material, what dripped off sagging films.
    pub dripped: Amount,
    /// Of the released material, what slumped over the edges of targets.
    pub ran_off: Amount,
}

impl Tally {
    /// Counts a particle's first impact on the front of a substrate target, carrying `volume`
    /// (m³), and, unless it `stuck`, its rebound from there.
    pub(crate) fn first_substrate_impact(&mut self, volume: f64, stuck: bool) {
        self.substrate_first_impacts.add(volume);
        if !stuck {
            self.substrate_first_rebounds.add(volume);
        }
    }
}

/// Running statistics of one path quantity and the samples outside its window.
#[derive(Clone, Copy, Debug, Default)]
pub struct Gauge {
    /// How many samples were taken.
    pub n: u64,
    /// Sum of the samples.
    pub sum: f64,
    /// Smallest sample.
    pub min: f64,
    /// Largest sample.
    pub max: f64,
    /// Samples outside the window.
    pub outside: u64,
}

impl Gauge {
    /// Adds a sample and whether it lies inside the recommended window.
    pub fn add(&mut self, x: f64, inside: bool) {
        if self.n == 0 {
            (self.min, self.max) = (x, x);
        }
        self.n += 1;
        self.sum += x;
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.outside += u64::from(!inside);
    }
}

/// Spraying-time statistics of the nozzle's path.
#[derive(Clone, Copy, Debug, Default)]
pub struct PathTally {
    /// Steps during which the nozzle sprayed.
    pub samples: u64,
    /// Distance along the axis to the first substrate surface, m.
    pub standoff: Gauge,
    /// Angle between the axis and that surface's normal, degrees.
    pub angle: Gauge,
    /// Travel speed along the path (without a superposed circle), m/s.
    pub travel_speed: Gauge,
    /// The nozzle's total speed, circle included, m/s.
    pub nozzle_speed: Gauge,
}
