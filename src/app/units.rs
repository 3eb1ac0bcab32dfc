//! Number formatting for labels: three significant digits, plain notation for everyday
//! magnitudes and scientific notation (like `1.2e-5`) for very small or large ones.

/// Format `v` with three significant digits.
pub fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    if (1e-3..1e4).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn formats() {
        assert_eq!(super::num(1.734), "1.73");
        assert_eq!(super::num(-0.0123), "-0.0123");
        assert_eq!(super::num(152.4), "152");
        assert_eq!(super::num(2.5e-6), "2.50e-6");
    }
}
