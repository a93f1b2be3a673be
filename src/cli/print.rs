//! What the commands print: the analysis of one dataset (Table 1, the independence tests, the
//! tails, the renewal check).

use crate::analysis;

pub(super) fn print_analysis(a: &analysis::Analysis) {
    let p_is = crate::figures::format::p_relation;
    println!("{}", analysis::output::table1_markdown(a));
    for j in &a.joints {
        if let Some(t) = &j.test {
            println!(
                "{} vs {}: chi2 = {:.1} (df {}), p {}; G p {}; MI = {:.2e} nats, permutation p {} -> {}",
                j.pair.0,
                j.pair.1,
                t.chi2,
                t.df,
                p_is(t.chi2_p_value),
                p_is(t.g_p_value),
                t.mutual_information,
                p_is(t.mi_p_value),
                analysis::output::verdict(t.chi2_p_value)
            );
        }
    }
    if let Some(t) = &a.tails {
        t.lines(&a.options.tail.times).iter().for_each(|l| println!("{l}"));
        if let Some(why) = &t.conditional_refused {
            eprintln!("note: no conditional tail estimate: {why}");
        }
    }
    if let Some(r) = &a.renewal {
        println!(
            "renewal check: E[S_T] predicted {:.2}, measured {:.2}; Var[S_T] predicted {:.2}, measured {:.2}",
            r.predicted_mean, r.measured_mean, r.predicted_variance, r.measured_variance
        );
    }
}
