//! `use breakaway::*;` compiles: no public item of the crate root is named
//! like the crate (a module `breakaway::breakaway` made the glob ambiguous,
//! E0659), and the main types come with it.

use breakaway::*;

mod support;

#[test]
fn glob_import_brings_the_main_types() {
    let model = Model::<f32>::new(support::FIG5).unwrap();
    let mut axis = Presliding::<i64>::new(0, 1e-8).unwrap();
    let force = axis.update(&model, 200, 1e-4).unwrap();
    assert!(force > 0.0 && force < 1.5);
    let predictor = BreakAwayPredictor::new(&model, DEFAULT_BOUNDARY).unwrap();
    let ba = predictor.predict(&model, Variant::Consistent, 2.0).unwrap();
    assert!(ba.f_ba > 1.0 && ba.f_ba < 1.5);
    // The modules come too.
    assert_eq!(predictor::DEFAULT_BOUNDARY, DEFAULT_BOUNDARY);
    assert!(compensation::FeedforwardConfig::default().gain == 1.0);
}
