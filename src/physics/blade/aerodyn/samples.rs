//! Sample AeroDyn files of the unit tests.

use std::path::{Path, PathBuf};

pub fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("windrive-aerodyn-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn put(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, text).unwrap();
    p
}

/// Columns in AeroDyn's order with two of the optional ones after BlAFID.
pub const BLADE: &str = "------- AERODYN v15.00.* BLADE DEFINITION INPUT FILE -------
A test blade
======  Blade Properties =====
          3   NumBlNds           - Number of blade nodes used in the analysis (-)
  BlSpn   BlCrvAC  BlSwpAC  BlCrvAng  BlTwist  BlChord  BlAFID  t_c  BlCb
   (m)      (m)      (m)     (deg)     (deg)     (m)     (-)    (-)  (-)
0.0000000E+00  0.0  0.0   0.0  1.3308000E+01  3.5420000E+00  1  1.0  0.0
5.0           -0.1  0.0   0.0  5.0            1.5            2  0.3  0.0
1.0000000E+01 -0.2  0.05 -1.5  0.0            1.0            2  0.2  0.0
";

pub const AIRFOIL: &str = "! ------------ AirfoilInfo v1.01.x Input File ------
! A test airfoil, two tables
! ------------------------------------------------------------------------------
\"DEFAULT\"     InterpOrd         ! Interpolation order
          1   NonDimArea        ! area
@\"coords.txt\"    NumCoords         ! coordinates in another file
          2   NumTabs           ! Number of airfoil tables in this file.
! data for table 1
       0.75   Re                ! Reynolds number in millions
          0   UserProp          ! User property (control) setting
True          InclUAdata        ! Is unsteady aerodynamics data included in this table?
       -3.2   alpha0            ! 0-lift angle of attack
          9   alpha1            ! stall
\"DEFAULT\"     UACutout          ! cut-out
          4   NumAlf            ! Number of data lines in the following table
!    Alpha      Cl      Cd        Cm
   -180.00    0.000   0.5000   0.0000
      0.00    0.300   0.0100  -0.0500
     10.00    1.200   0.0200  -0.0600
    180.00    0.000   0.5000   0.0000
! data for table 2
        1.5   Re
          0   UserProp
False         InclUAdata
          2   NumAlf
   -180.00    0.000   0.5000   0.0000
    180.00    0.000   0.5000   0.0000
";
