//! The simulated controller clock: what `CDate` and `GetTime` read. A
//! test sets and advances it, so that a day of running and stopping is
//! simulated in no time.

/// Seconds since 2000-01-01 00:00:00 (the controller's clock has whole
/// seconds; a fraction is kept but `GetTime(\Sec)` reads it whole).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clock {
    seconds: f64,
}

impl Clock {
    /// The clock at a civil date and time.
    pub fn at(year: i64, month: i64, day: i64, hour: i64, minute: i64, second: i64) -> Clock {
        let days = days_from_civil(year, month, day);
        Clock {
            seconds: (days * 86_400 + hour * 3600 + minute * 60 + second) as f64,
        }
    }
    /// Moves the clock on by `minutes`.
    pub fn advance(&mut self, minutes: f64) {
        self.seconds += minutes * 60.0;
    }
    /// The clock `minutes` later.
    pub fn plus(self, minutes: f64) -> Clock {
        Clock {
            seconds: self.seconds + minutes * 60.0,
        }
    }
    /// Minutes since 2000-01-01.
    pub fn minutes(&self) -> f64 {
        self.seconds / 60.0
    }
    fn whole(&self) -> i64 {
        self.seconds.floor() as i64
    }
    /// `CDate()`: `"YYYY-MM-DD"`.
    pub fn date(&self) -> String {
        let (y, m, d) = civil_from_days(self.whole().div_euclid(86_400));
        format!("{y:04}-{m:02}-{d:02}")
    }
    /// `CTime()`: `"HH:MM:SS"`.
    pub fn time(&self) -> String {
        let (h, m, s) = self.hms();
        format!("{h:02}:{m:02}:{s:02}")
    }
    /// Hour, minute and second of the day.
    pub fn hms(&self) -> (i64, i64, i64) {
        let s = self.whole().rem_euclid(86_400);
        (s / 3600, s / 60 % 60, s % 60)
    }
    /// Day of the week, 0 Sunday .. 6 Saturday (`GetTime(\WDay)`).
    pub fn weekday(&self) -> i64 {
        // 2000-01-01 was a Saturday.
        (self.whole().div_euclid(86_400) + 6).rem_euclid(7)
    }
}

/// Days from 2000-01-01 to a civil date (proleptic Gregorian; H. Hinnant's
/// days-from-civil).
pub fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = if m > 2 { m - 3 } else { m + 9 };
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 730_425
}

/// The civil date of a day since 2000-01-01 (the inverse of
/// [`days_from_civil`]).
pub fn civil_from_days(n: i64) -> (i64, i64, i64) {
    let z = n + 730_425;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_go_both_ways() {
        for n in [-800_000, -1, 0, 59, 60, 8825, 9827, 36_584, 400_000] {
            let (y, m, d) = civil_from_days(n);
            assert_eq!(days_from_civil(y, m, d), n);
        }
        assert_eq!(civil_from_days(8825), (2024, 2, 29));
        let c = Clock::at(2026, 11, 27, 23, 59, 30);
        assert_eq!(c.date(), "2026-11-27");
        assert_eq!(c.plus(1.0).date(), "2026-11-28");
        assert_eq!(c.plus(1.0).time(), "00:00:30");
        assert_eq!(c.weekday(), 5, "a Friday");
    }
}
