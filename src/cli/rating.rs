//! What `windrive gears` and `windrive bearings` share: their output options and printer.

/// The options `windrive gears` and `windrive bearings` share.
#[derive(clap::Args)]
pub struct RatingOptions {
    /// Seconds at the start left out (the paper discards the first 20 s of its 80 s)
    #[arg(long, default_value_t = 0.0)]
    pub transient: f64,
    /// Print the results as JSON (one object per rated tooth or bearing)
    #[arg(long)]
    pub json: bool,
    /// Print the channels the rating reads (for `windrive run --record`), one per line, and stop
    #[arg(long)]
    pub channels: bool,
}

impl RatingOptions {
    pub fn check(&self) -> anyhow::Result<()> {
        if !(self.transient.is_finite() && self.transient >= 0.0) {
            anyhow::bail!("--transient {}: must be a number ≥ 0", self.transient);
        }
        Ok(())
    }
}

/// Prints `rated` as pretty JSON with `json`, else as `text` formats it (the rating commands' output).
pub fn print_rated<T: serde::Serialize>(rated: &[T], json: bool, text: fn(&[T]) -> String) -> anyhow::Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(rated)?);
    } else {
        print!("{}", text(rated));
    }
    Ok(())
}
