//! Running totals the pipeline keeps as it goes: amounts of particles and volume, and the
//! statistics of the nozzle's path.

/// A number of particles and the material volume they carry, m³: what the metrics report.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Amount {
    /// How many particles.
    pub count: u64,
    /// Volume, m³.
    pub volume: f64,
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

/// Volume counted in whole quanta of a run's volume quantum (see
/// [`crate::SimulationConfig::volume_quantum`]): sums of quanta are exact, so totals gathered
/// by several threads in any order, and merged in any order, come out the same to the bit.
pub type Quanta = u128;

/// A number of particles and the volume they carry, in quanta: what the run books as it goes
/// (in flight, by any number of threads), exact and independent of the order of its additions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tallied {
    /// How many particles.
    pub count: u64,
    /// Their volume, in quanta of the run's volume quantum.
    pub quanta: Quanta,
}

impl Tallied {
    /// Adds one particle of `quanta` volume.
    #[inline]
    pub fn add(&mut self, quanta: u64) {
        self.count += 1;
        self.quanta += Quanta::from(quanta);
    }

    /// This tally as particles and m³, with the run's volume quantum `q` (m³).
    pub fn amount(&self, q: f64) -> Amount {
        Amount { count: self.count, volume: self.quanta as f64 * q }
    }

    /// The volume, m³, with the run's volume quantum `q` (m³).
    pub fn volume(&self, q: f64) -> f64 {
        self.quanta as f64 * q
    }
}

impl std::ops::AddAssign for Tallied {
    fn add_assign(&mut self, o: Tallied) {
        self.count += o.count;
        self.quanta += o.quanta;
    }
}

impl std::ops::Add for Tallied {
    type Output = Tallied;
    fn add(mut self, o: Tallied) -> Tallied {
        self += o;
        self
    }
}

impl std::iter::Sum for Tallied {
    fn sum<I: Iterator<Item = Tallied>>(iter: I) -> Tallied {
        iter.fold(Tallied::default(), |a, b| a + b)
    }
}

/// Running totals over the whole run, in quanta (see [`Tallied`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tally {
    /// Particles emitted.
    pub emitted: Tallied,
    /// Particles that left the domain box after striking something.
    pub left_domain: Tallied,
    /// Particles retired past the maximum lifetime after striking something.
    pub expired: Tallied,
    /// Overspray: particles from the nozzle that never struck a surface and left flight, by
    /// leaving the domain, expiring, or drifting out of the gun's air into the booth's.
    pub overspray: Tallied,
    /// Particles whose first substrate impact happened.
    pub substrate_first_impacts: Tallied,
    /// Of those, the ones that rebounded from it.
    pub substrate_first_rebounds: Tallied,
    /// Particles released by cohesive failures, drips and slumps.
    pub released: Tallied,
    /// Released particles that left the domain.
    pub released_left: Tallied,
    /// Released particles that expired.
    pub released_expired: Tallied,
    /// Of the released material, what dripped off sagging films.
    pub dripped: Tallied,
    /// Of the released material, what slumped over the edges of targets.
    pub ran_off: Tallied,
}

impl Tally {
    /// Counts a particle's first impact on the front of a substrate target, carrying `quanta`
    /// of volume, and, unless it `stuck`, its rebound from there.
    pub(crate) fn first_substrate_impact(&mut self, quanta: u64, stuck: bool) {
        self.substrate_first_impacts.add(quanta);
        if !stuck {
            self.substrate_first_rebounds.add(quanta);
        }
    }

    /// Adds `o`'s totals to these.
    pub(crate) fn merge(&mut self, o: &Tally) {
        self.emitted += o.emitted;
        self.left_domain += o.left_domain;
        self.expired += o.expired;
        self.overspray += o.overspray;
        self.substrate_first_impacts += o.substrate_first_impacts;
        self.substrate_first_rebounds += o.substrate_first_rebounds;
        self.released += o.released;
        self.released_left += o.released_left;
        self.released_expired += o.released_expired;
        self.dripped += o.dripped;
        self.ran_off += o.ran_off;
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
