//! Gauss rules on [0, 1] for the quadrature of law 4 (nodes ascending, weights matching).
//!
//! Computed by the Golub-Welsch method (the Stieltjes recurrence from the exact moments,
//! then the eigenvalues of the Jacobi matrix) in 120-digit arithmetic and rounded to 25
//! digits; the Gauss-Legendre rules of 2, 4 and 6 points by Newton's method on the
//! Legendre polynomial (three-term recurrence) in 60-digit arithmetic, also rounded to 25
//! digits. Gauss-Legendre: weight 1 (the weights sum to 1). Gauss-Jacobi: weight
//! `u^(b3 - 1)` with b3 = 1.036077 of [`super::XU_B`] (the weights sum to 1/b3), exact for
//! `u^(b3 - 1) g(u)` with g of degree <= 2n - 1. At the Gauss-Jacobi nodes, the weights of
//! the interpolatory rule for the weight `u^(b3 - 2)` (exact for `u^(b3 - 2) g(u)` with g of
//! degree <= n - 1; the moment equations solved in 80-digit arithmetic), for the first-order
//! term of the axial-sliding expansion in `quadrature`.

/// An N-point Gauss rule on [0, 1].
pub(super) struct Rule<const N: usize> {
    /// Nodes in (0, 1), ascending.
    pub x: [f64; N],
    /// Weights.
    pub w: [f64; N],
}

impl<const N: usize> Rule<N> {
    /// The rule with nodes x and weights w.
    pub const fn new(x: [f64; N], w: [f64; N]) -> Self {
        Rule { x, w }
    }
}

/// Nodes of the 8-point Gauss-Jacobi for the weight u^(b3 - 1).
#[allow(clippy::excessive_precision)]
pub(super) const GJ8_X: [f64; 8] = [
    0.02068744582211924014198953,
    0.1032549824268569461885552,
    0.2391411566784287820293917,
    0.4101041501358960393201118,
    0.5931558708668661403296209,
    0.7636798828508523156680631,
    0.8987472804122804252805815,
    0.9802281898413817230095011,
];
/// Weights of the 8-point Gauss-Jacobi for the weight u^(b3 - 1).
#[allow(clippy::excessive_precision)]
pub(super) const GJ8_W: [f64; 8] = [
    0.04483956832031630535470332,
    0.1029428475252431697200277,
    0.1490615514754832568333941,
    0.1753539637811799894630995,
    0.1774838889041625326513913,
    0.1548009957483329695753095,
    0.1103292595008486991824531,
    0.05036715370135423269358717,
];
/// Nodes of the 10-point Gauss-Jacobi for the weight u^(b3 - 1).
#[allow(clippy::excessive_precision)]
pub(super) const GJ10_X: [f64; 10] = [
    0.01360589547743964543239369,
    0.06858973046460977543235409,
    0.1617501380404860071006181,
    0.284859238705912304881841,
    0.427018318138211318265266,
    0.5756397051964843039148459,
    0.7175631649795189378892784,
    0.8402219083695105710997883,
    0.9327572008221804263742605,
    0.9869977097262015168203665,
];
/// Weights of the 10-point Gauss-Jacobi for the weight u^(b3 - 1).
#[allow(clippy::excessive_precision)]
pub(super) const GJ10_W: [f64; 10] = [
    0.0291181275182110984627061,
    0.06824965269248015318274483,
    0.1027770415970526500183958,
    0.1286636856942122056238456,
    0.143113098279020803409052,
    0.144546196604289784719233,
    0.1326803497354082917225806,
    0.1085289929616676335003349,
    0.07429515627969804919202093,
    0.03320692759488048564305199,
];
/// Nodes of the 12-point Gauss-Jacobi for the weight u^(b3 - 1).
#[allow(clippy::excessive_precision)]
pub(super) const GJ12_X: [f64; 12] = [
    0.009620604614611260941843075,
    0.04877014284674559668390706,
    0.1161729040536055863271233,
    0.20762103709705157140186,
    0.3173869378424148799627164,
    0.4385938749020363059735639,
    0.5636479947578594685979762,
    0.684714344717366549562704,
    0.7942078828337401733241251,
    0.8852689554278205986148927,
    0.9521942791713917860865664,
    0.9908067542732216986567848,
];
/// Weights of the 12-point Gauss-Jacobi for the weight u^(b3 - 1).
#[allow(clippy::excessive_precision)]
pub(super) const GJ12_W: [f64; 12] = [
    0.02036073343322836395802269,
    0.04827565481289354861770241,
    0.07426714004606861245235045,
    0.0960650478110836432550288,
    0.1119742285505855746587396,
    0.1207871841043676395425728,
    0.1218157029392922801734731,
    0.1149179216483541925545787,
    0.1004987117992953261684287,
    0.07947772541997000096387906,
    0.0532267729191506764990763,
    0.02351240547263129663011324,
];

/// Weights of the 8-point interpolatory rule for the weight u^(b3 - 2) at the nodes of
/// the 8-point Gauss-Jacobi rule ([`GJ8_X`]).
#[allow(clippy::excessive_precision)]
pub(super) const GJ8_W2: [f64; 8] = [
    38.81526646835135022164404,
    -22.78713332087962847504025,
    17.94609866784192100836253,
    -12.20546637669476246203458,
    9.075670461897377661911180,
    -5.302727820846111548198536,
    2.927157594826907152656459,
    -0.7503746691473847952683619,
];
/// Weights of the 10-point interpolatory rule for the weight u^(b3 - 2) at the nodes of
/// the 10-point Gauss-Jacobi rule ([`GJ10_X`]).
#[allow(clippy::excessive_precision)]
pub(super) const GJ10_W2: [f64; 10] = [
    38.41046868080250306362251,
    -23.03749587008018135407263,
    18.85425445776697604758759,
    -13.73619055756764797792408,
    11.27458924391307670391217,
    -7.897884609555507990639429,
    5.889729383293519837687327,
    -3.457102647675632711247419,
    1.906603738240833480046824,
    -0.4884808137882703349403713,
];
/// Weights of the 12-point interpolatory rule for the weight u^(b3 - 2) at the nodes of
/// the 12-point Gauss-Jacobi rule ([`GJ12_X`]).
#[allow(clippy::excessive_precision)]
pub(super) const GJ12_W2: [f64; 12] = [
    38.03162800705589764500214,
    -23.08215764550154715369085,
    19.28642324436972423363064,
    -14.55821396843356379383913,
    12.52683438468504694868919,
    -9.479000399244212330113500,
    7.834258280099795033064994,
    -5.538721170029723720415274,
    4.129766555200129158314827,
    -2.427946815443464819104496,
    1.338303228968390049779500,
    -0.3426826963768024872855449,
];

/// Nodes of the 2-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL2_X: [f64; 2] = [0.2113248654051871177454256, 0.7886751345948128822545744];
/// Weights of the 2-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL2_W: [f64; 2] = [0.5000000000000000000000000, 0.5000000000000000000000000];
/// Nodes of the 4-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL4_X: [f64; 4] = [
    0.06943184420297371238802676,
    0.3300094782075718675986671,
    0.6699905217924281324013329,
    0.9305681557970262876119732,
];
/// Weights of the 4-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL4_W: [f64; 4] = [
    0.1739274225687269286865320,
    0.3260725774312730713134680,
    0.3260725774312730713134680,
    0.1739274225687269286865320,
];
/// Nodes of the 6-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL6_X: [f64; 6] = [
    0.03376524289842398609384922,
    0.1693953067668677431693002,
    0.3806904069584015456847491,
    0.6193095930415984543152509,
    0.8306046932331322568306998,
    0.9662347571015760139061508,
];
/// Weights of the 6-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL6_W: [f64; 6] = [
    0.08566224618958517252014807,
    0.1803807865240693037849168,
    0.2339569672863455236949352,
    0.2339569672863455236949352,
    0.1803807865240693037849168,
    0.08566224618958517252014807,
];
/// Nodes of the 8-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(in crate::gear::friction) const GL8_X: [f64; 8] = [
    0.01985507175123188415821957,
    0.101666761293186630204223,
    0.2372337950418355070911305,
    0.4082826787521750975302619,
    0.5917173212478249024697381,
    0.7627662049581644929088695,
    0.898333238706813369795777,
    0.9801449282487681158417804,
];
/// Weights of the 8-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(in crate::gear::friction) const GL8_W: [f64; 8] = [
    0.05061426814518812957626568,
    0.111190517226687235272178,
    0.1568533229389436436689811,
    0.1813418916891809914825752,
    0.1813418916891809914825752,
    0.1568533229389436436689811,
    0.111190517226687235272178,
    0.05061426814518812957626568,
];
/// Nodes of the 10-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL10_X: [f64; 10] = [
    0.01304673574141413996101799,
    0.06746831665550774463395166,
    0.1602952158504877968828363,
    0.283302302935376404600367,
    0.425562830509184394557587,
    0.574437169490815605442413,
    0.716697697064623595399633,
    0.8397047841495122031171637,
    0.9325316833444922553660483,
    0.986953264258585860038982,
];
/// Weights of the 10-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL10_W: [f64; 10] = [
    0.0333356721543440687967844,
    0.07472567457529029657288817,
    0.1095431812579910219977675,
    0.1346333596549981775456135,
    0.1477621123573764350869465,
    0.1477621123573764350869465,
    0.1346333596549981775456135,
    0.1095431812579910219977675,
    0.07472567457529029657288817,
    0.0333356721543440687967844,
];

/// Nodes of the 16-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL16_X: [f64; 16] = [
    0.005299532504175033701922913,
    0.02771248846338371196100579,
    0.06718439880608412805976605,
    0.1222977958224984830524494,
    0.1910618777986781257766641,
    0.2709916111713863068287903,
    0.3591982246103705433847697,
    0.4524937450811812799073403,
    0.5475062549188187200926597,
    0.6408017753896294566152303,
    0.7290083888286136931712097,
    0.8089381222013218742233359,
    0.8777022041775015169475506,
    0.9328156011939158719402339,
    0.9722875115366162880389942,
    0.9947004674958249662980771,
];
/// Weights of the 16-point Gauss-Legendre.
#[allow(clippy::excessive_precision)]
pub(super) const GL16_W: [f64; 16] = [
    0.01357622970587704742589029,
    0.03112676196932394643142192,
    0.04757925584124639240496255,
    0.06231448562776693602623814,
    0.07479799440828836604075087,
    0.08457825969750126909465604,
    0.09130170752246179443338183,
    0.09472530522753424814269836,
    0.09472530522753424814269836,
    0.09130170752246179443338183,
    0.08457825969750126909465604,
    0.07479799440828836604075087,
    0.06231448562776693602623814,
    0.04757925584124639240496255,
    0.03112676196932394643142192,
    0.01357622970587704742589029,
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gear::friction::ehl::XU_B;

    /// `sum w x^k` against the exact moments `1/(k + 1 + beta)` for every degree the rule
    /// integrates exactly (k <= 2n - 1): a wrong digit in a node or weight shows here.
    fn check<const N: usize>(x: &[f64; N], w: &[f64; N], beta: f64) -> f64 {
        let mut worst: f64 = 0.0;
        for k in 0..2 * N as i32 {
            let q: f64 = x.iter().zip(w).map(|(&u, &v)| v * u.powi(k)).sum();
            let exact = 1.0 / (k as f64 + 1.0 + beta);
            worst = worst.max((q - exact).abs() / exact);
        }
        worst
    }

    #[test]
    fn rules_integrate_their_polynomials_exactly() {
        let beta = XU_B[2] - 1.0;
        let errs = [
            check(&GJ8_X, &GJ8_W, beta),
            check(&GJ10_X, &GJ10_W, beta),
            check(&GJ12_X, &GJ12_W, beta),
            check(&GL2_X, &GL2_W, 0.0),
            check(&GL4_X, &GL4_W, 0.0),
            check(&GL6_X, &GL6_W, 0.0),
            check(&GL8_X, &GL8_W, 0.0),
            check(&GL10_X, &GL10_W, 0.0),
            check(&GL16_X, &GL16_W, 0.0),
        ];
        for e in errs {
            assert!(e < 1e-13, "{errs:?}");
        }
        // the interpolatory rules for u^(b3 - 2): exact to degree n - 1, moments 1/(k + b3 - 1)
        let interp = |x: &[f64], w: &[f64]| {
            let mut worst: f64 = 0.0;
            for k in 0..x.len() as i32 {
                let q: f64 = x.iter().zip(w).map(|(&u, &v)| v * u.powi(k)).sum();
                let exact = 1.0 / (k as f64 + beta);
                worst = worst.max((q - exact).abs() / exact);
            }
            worst
        };
        let errs2 = [
            interp(&GJ8_X, &GJ8_W2),
            interp(&GJ10_X, &GJ10_W2),
            interp(&GJ12_X, &GJ12_W2),
        ];
        for e in errs2 {
            assert!(e < 1e-12, "{errs2:?}");
        }
    }
}
