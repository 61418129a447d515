#include "numerics/dop853.hpp"

#include <cmath>

namespace ajx::numerics {
namespace {

// Coefficients of DOP853: E. Hairer, S.P. Norsett, G. Wanner, Solving Ordinary Differential
// Equations I, 2nd ed., Springer 1993, Sect. II.10 (method of Dormand & Prince 1980 with
// Hairer's error estimator and dense output), as given in the authors' dop853.f.
constexpr double c2 = 0.526001519587677318785587544488e-01;
constexpr double c3 = 0.789002279381515978178381316732e-01;
constexpr double c4 = 0.118350341907227396726757197510e+00;
constexpr double c5 = 0.281649658092772603273242802490e+00;
constexpr double c6 = 0.333333333333333333333333333333e+00;
constexpr double c7 = 0.25e+00;
constexpr double c8 = 0.307692307692307692307692307692e+00;
constexpr double c9 = 0.651282051282051282051282051282e+00;
constexpr double c10 = 0.6e+00;
constexpr double c11 = 0.857142857142857142857142857142e+00;
constexpr double c14 = 0.1e+00;
constexpr double c15 = 0.2e+00;
constexpr double c16 = 0.777777777777777777777777777778e+00;

constexpr double b1 = 5.42937341165687622380535766363e-2;
constexpr double b6 = 4.45031289275240888144113950566e0;
constexpr double b7 = 1.89151789931450038304281599044e0;
constexpr double b8 = -5.8012039600105847814672114227e0;
constexpr double b9 = 3.1116436695781989440891606237e-1;
constexpr double b10 = -1.52160949662516078556178806805e-1;
constexpr double b11 = 2.01365400804030348374776537501e-1;
constexpr double b12 = 4.47106157277725905176885569043e-2;

// 3rd-order estimator: b - bhh with bhh on stages 1, 9, 12.
constexpr double bhh1 = 0.244094488188976377952755905512e+00;
constexpr double bhh2 = 0.733846688281611857341361741547e+00;
constexpr double bhh3 = 0.220588235294117647058823529412e-01;

// 5th-order estimator: b - b5.
constexpr double er1 = 0.1312004499419488073250102996e-01;
constexpr double er6 = -0.1225156446376204440720569753e+01;
constexpr double er7 = -0.4957589496572501915214079952e+00;
constexpr double er8 = 0.1664377182454986536961530415e+01;
constexpr double er9 = -0.3503288487499736816886487290e+00;
constexpr double er10 = 0.3341791187130174790297318841e+00;
constexpr double er11 = 0.8192320648511571246570742613e-01;
constexpr double er12 = -0.2235530786388629525884427845e-01;

constexpr double a21 = 5.26001519587677318785587544488e-2;
constexpr double a31 = 1.97250569845378994544595329183e-2;
constexpr double a32 = 5.91751709536136983633785987549e-2;
constexpr double a41 = 2.95875854768068491816892993775e-2;
constexpr double a43 = 8.87627564304205475450678981324e-2;
constexpr double a51 = 2.41365134159266685502369798665e-1;
constexpr double a53 = -8.84549479328286085344864962717e-1;
constexpr double a54 = 9.24834003261792003115737966543e-1;
constexpr double a61 = 3.7037037037037037037037037037e-2;
constexpr double a64 = 1.70828608729473871279604482173e-1;
constexpr double a65 = 1.25467687566822425016691814123e-1;
constexpr double a71 = 3.7109375e-2;
constexpr double a74 = 1.70252211019544039314978060272e-1;
constexpr double a75 = 6.02165389804559606850219397283e-2;
constexpr double a76 = -1.7578125e-2;
constexpr double a81 = 3.70920001185047927108779319836e-2;
constexpr double a84 = 1.70383925712239993810214054705e-1;
constexpr double a85 = 1.07262030446373284651809199168e-1;
constexpr double a86 = -1.53194377486244017527936158236e-2;
constexpr double a87 = 8.27378916381402288758473766002e-3;
constexpr double a91 = 6.24110958716075717114429577812e-1;
constexpr double a94 = -3.36089262944694129406857109825e0;
constexpr double a95 = -8.68219346841726006818189891453e-1;
constexpr double a96 = 2.75920996994467083049415600797e1;
constexpr double a97 = 2.01540675504778934086186788979e1;
constexpr double a98 = -4.34898841810699588477366255144e1;
constexpr double a101 = 4.77662536438264365890433908527e-1;
constexpr double a104 = -2.48811461997166764192642586468e0;
constexpr double a105 = -5.90290826836842996371446475743e-1;
constexpr double a106 = 2.12300514481811942347288949897e1;
constexpr double a107 = 1.52792336328824235832596922938e1;
constexpr double a108 = -3.32882109689848629194453265587e1;
constexpr double a109 = -2.03312017085086261358222928593e-2;
constexpr double a111 = -9.3714243008598732571704021658e-1;
constexpr double a114 = 5.18637242884406370830023853209e0;
constexpr double a115 = 1.09143734899672957818500254654e0;
constexpr double a116 = -8.14978701074692612513997267357e0;
constexpr double a117 = -1.85200656599969598641566180701e1;
constexpr double a118 = 2.27394870993505042818970056734e1;
constexpr double a119 = 2.49360555267965238987089396762e0;
constexpr double a1110 = -3.0467644718982195003823669022e0;
constexpr double a121 = 2.27331014751653820792359768449e0;
constexpr double a124 = -1.05344954667372501984066689879e1;
constexpr double a125 = -2.00087205822486249909675718444e0;
constexpr double a126 = -1.79589318631187989172765950534e1;
constexpr double a127 = 2.79488845294199600508499808837e1;
constexpr double a128 = -2.85899827713502369474065508674e0;
constexpr double a129 = -8.87285693353062954433549289258e0;
constexpr double a1210 = 1.23605671757943030647266201528e1;
constexpr double a1211 = 6.43392746015763530355970484046e-1;

// Extra stages 14-16 of the dense output (stage 13 is f(t1, y1)).
constexpr double a141 = 5.61675022830479523392909219681e-2;
constexpr double a147 = 2.53500210216624811088794765333e-1;
constexpr double a148 = -2.46239037470802489917441475441e-1;
constexpr double a149 = -1.24191423263816360469010140626e-1;
constexpr double a1410 = 1.5329179827876569731206322685e-1;
constexpr double a1411 = 8.20105229563468988491666602057e-3;
constexpr double a1412 = 7.56789766054569976138603589584e-3;
constexpr double a1413 = -8.298e-3;
constexpr double a151 = 3.18346481635021405060768473261e-2;
constexpr double a156 = 2.83009096723667755288322961402e-2;
constexpr double a157 = 5.35419883074385676223797384372e-2;
constexpr double a158 = -5.49237485713909884646569340306e-2;
constexpr double a1511 = -1.08347328697249322858509316994e-4;
constexpr double a1512 = 3.82571090835658412954920192323e-4;
constexpr double a1513 = -3.40465008687404560802977114492e-4;
constexpr double a1514 = 1.41312443674632500278074618366e-1;
constexpr double a161 = -4.28896301583791923408573538692e-1;
constexpr double a166 = -4.69762141536116384314449447206e0;
constexpr double a167 = 7.68342119606259904184240953878e0;
constexpr double a168 = 4.06898981839711007970213554331e0;
constexpr double a169 = 3.56727187455281109270669543021e-1;
constexpr double a1613 = -1.39902416515901462129418009734e-3;
constexpr double a1614 = 2.9475147891527723389556272149e0;
constexpr double a1615 = -9.15095847217987001081870187138e0;

// Dense-output coefficients d_{k,i}, k = 4..7 (rows of the polynomial), i = stage.
constexpr double d41 = -0.84289382761090128651353491142e+01;
constexpr double d46 = 0.56671495351937776962531783590e+00;
constexpr double d47 = -0.30689499459498916912797304727e+01;
constexpr double d48 = 0.23846676565120698287728149680e+01;
constexpr double d49 = 0.21170345824450282767155149946e+01;
constexpr double d410 = -0.87139158377797299206789907490e+00;
constexpr double d411 = 0.22404374302607882758541771650e+01;
constexpr double d412 = 0.63157877876946881815570249290e+00;
constexpr double d413 = -0.88990336451333310820698117400e-01;
constexpr double d414 = 0.18148505520854727256656404962e+02;
constexpr double d415 = -0.91946323924783554000451984436e+01;
constexpr double d416 = -0.44360363875948939664310572000e+01;
constexpr double d51 = 0.10427508642579134603413151009e+02;
constexpr double d56 = 0.24228349177525818288430175319e+03;
constexpr double d57 = 0.16520045171727028198505394887e+03;
constexpr double d58 = -0.37454675472269020279518312152e+03;
constexpr double d59 = -0.22113666853125306036270938578e+02;
constexpr double d510 = 0.77334326684722638389603898808e+01;
constexpr double d511 = -0.30674084731089398182061213626e+02;
constexpr double d512 = -0.93321305264302278729567221706e+01;
constexpr double d513 = 0.15697238121770843886131091075e+02;
constexpr double d514 = -0.31139403219565177677282850411e+02;
constexpr double d515 = -0.93529243588444783865713862664e+01;
constexpr double d516 = 0.35816841486394083752465898540e+02;
constexpr double d61 = 0.19985053242002433820987653617e+02;
constexpr double d66 = -0.38703730874935176555105901742e+03;
constexpr double d67 = -0.18917813819516756882830838328e+03;
constexpr double d68 = 0.52780815920542364900561016686e+03;
constexpr double d69 = -0.11573902539959630126141871134e+02;
constexpr double d610 = 0.68812326946963000169666922661e+01;
constexpr double d611 = -0.10006050966910838403183860980e+01;
constexpr double d612 = 0.77771377980534432092869265740e+00;
constexpr double d613 = -0.27782057523535084065932004339e+01;
constexpr double d614 = -0.60196695231264120758267380846e+02;
constexpr double d615 = 0.84320405506677161018159903784e+02;
constexpr double d616 = 0.11992291136182789328035130030e+02;
constexpr double d71 = -0.25693933462703749003312586129e+02;
constexpr double d76 = -0.15418974869023643374053993627e+03;
constexpr double d77 = -0.23152937917604549567536039109e+03;
constexpr double d78 = 0.35763911791061412378285349910e+03;
constexpr double d79 = 0.93405324183624310003907691704e+02;
constexpr double d710 = -0.37458323136451633156875139351e+02;
constexpr double d711 = 0.10409964950896230045147246184e+03;
constexpr double d712 = 0.29840293426660503123344363579e+02;
constexpr double d713 = -0.43533456590011143754432175058e+02;
constexpr double d714 = 0.96324553959188282948394950600e+02;
constexpr double d715 = -0.39177261675615439165231486172e+02;
constexpr double d716 = -0.14972683625798562581422125276e+03;

}  // namespace

double Dop853::attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                       const Tolerances& tol) {
  return with_state_size(y.size(), [&]<int N>() { return attempt_n<N>(f, t, y, h, y_new, tol); });
}

// The stage combinations on fixed-size maps of the member vectors when N is a compile-time
// size (vector.hpp): the same element-wise arithmetic, without the length loops.
template <int N>
double Dop853::attempt_n(const System& f, double t, const Vec& y, double h, Vec& y_new,
                         const Tolerances& tol) {
  using M = Eigen::Map<Eigen::Matrix<double, N, 1>, Eigen::Aligned16>;
  const auto n = y.size();
  y0_ = y;  // first: y_new may alias y
  for (Vec* v : {&tmp_, &y1_, &k2_, &k3_, &k4_, &k5_, &k6_, &k7_, &k8_, &k9_, &k10_, &k11_, &k12_})
    v->resize(n);
  cache_.get(f, t, y0_, k1_, rhs_evals_);
  const M y0(y0_.data(), n);
  M y1(y1_.data(), n), tmp(tmp_.data(), n);
  const M k1(k1_.data(), n), k2(k2_.data(), n), k3(k3_.data(), n), k4(k4_.data(), n), k5(k5_.data(), n),
      k6(k6_.data(), n), k7(k7_.data(), n), k8(k8_.data(), n), k9(k9_.data(), n), k10(k10_.data(), n),
      k11(k11_.data(), n), k12(k12_.data(), n);

  tmp = y0 + (h * a21) * k1;
  f(t + c2 * h, tmp_, k2_);
  tmp = y0 + h * (a31 * k1 + a32 * k2);
  f(t + c3 * h, tmp_, k3_);
  tmp = y0 + h * (a41 * k1 + a43 * k3);
  f(t + c4 * h, tmp_, k4_);
  tmp = y0 + h * (a51 * k1 + a53 * k3 + a54 * k4);
  f(t + c5 * h, tmp_, k5_);
  tmp = y0 + h * (a61 * k1 + a64 * k4 + a65 * k5);
  f(t + c6 * h, tmp_, k6_);
  tmp = y0 + h * (a71 * k1 + a74 * k4 + a75 * k5 + a76 * k6);
  f(t + c7 * h, tmp_, k7_);
  tmp = y0 + h * (a81 * k1 + a84 * k4 + a85 * k5 + a86 * k6 + a87 * k7);
  f(t + c8 * h, tmp_, k8_);
  tmp = y0 + h * (a91 * k1 + a94 * k4 + a95 * k5 + a96 * k6 + a97 * k7 + a98 * k8);
  f(t + c9 * h, tmp_, k9_);
  tmp = y0 + h * (a101 * k1 + a104 * k4 + a105 * k5 + a106 * k6 + a107 * k7 + a108 * k8 + a109 * k9);
  f(t + c10 * h, tmp_, k10_);
  tmp = y0 + h * (a111 * k1 + a114 * k4 + a115 * k5 + a116 * k6 + a117 * k7 + a118 * k8 + a119 * k9 +
                  a1110 * k10);
  f(t + c11 * h, tmp_, k11_);
  tmp = y0 + h * (a121 * k1 + a124 * k4 + a125 * k5 + a126 * k6 + a127 * k7 + a128 * k8 + a129 * k9 +
                  a1210 * k10 + a1211 * k11);
  f(t + h, tmp_, k12_);
  rhs_evals_ += 11;

  // y1 = y0 + h sum b_i k_i; tmp holds the increment direction sum b_i k_i.
  tmp = b1 * k1 + b6 * k6 + b7 * k7 + b8 * k8 + b9 * k9 + b10 * k10 + b11 * k11 + b12 * k12;
  y1 = y0 + h * tmp;

  // Error (dop853.f): err5_i = h sum er_j k_j, err3_i = h (sum b k - bhh1 k1 - bhh2 k9 -
  // bhh3 k12); with s_i = atol + rtol max(|y0_i|, |y1_i|), E5 = sum (err5_i/s_i)^2,
  // E3 = sum (err3_i/s_i)^2: err = E5 / sqrt(n (E5 + 0.01 E3)). Asymptotically
  // err ~ |err5|^2/|err3| = O(h^8), so the controller treats it as an order-7 estimate.
  double e5 = 0.0, e3 = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double sk = tol.atol + tol.rtol * std::max(std::abs(y0[i]), std::abs(y1[i]));
    const double r3 = (tmp[i] - bhh1 * k1[i] - bhh2 * k9[i] - bhh3 * k12[i]) / sk;
    const double r5 = (er1 * k1[i] + er6 * k6[i] + er7 * k7[i] + er8 * k8[i] + er9 * k9[i] + er10 * k10[i] +
                       er11 * k11[i] + er12 * k12[i]) /
                      sk;
    e3 += r3 * r3;
    e5 += r5 * r5;
  }
  double deno = e5 + 0.01 * e3;
  if (deno <= 0.0) deno = 1.0;
  const double err = std::abs(h) * e5 / std::sqrt(static_cast<double>(n) * deno);

  t_ = t;
  h_ = h;
  dense_ready_ = false;
  hermite_ready_ = false;
  y_new = y1_;
  return err;
}

// Nothing to store: f(t1, y1) is evaluated at most once, by the next attempt (k1) or by
// dense() (k13), whichever comes first, and shared through the cache.
void Dop853::accept(const System& /*f*/) {}

// r0..r3 of the dense output, which alone are the cubic Hermite interpolant through (y0, f0) and
// (y1, f1): r0 = y0, r1 = y1 - y0, r2 = h k1 - r1, r3 = r1 - h k13 - r2.
void Dop853::prepare_hermite(const System& f) {
  const auto n = y0_.size();
  const double t1 = t_ + h_;
  // Stage 13 = f(t1, y1), shared with the next step's k1.
  if (cache_.holds(t1, y1_)) {
    k13_ = cache_.value();
  } else {
    k13_.resize(n);
    f(t1, y1_, k13_);
    ++rhs_evals_;
    cache_.offer(t1, y1_, k13_);
  }
  r_[0] = y0_;
  r_[1] = y1_ - y0_;
  r_[2] = h_ * k1_ - r_[1];
  r_[3] = r_[1] - h_ * k13_ - r_[2];
  hermite_ready_ = true;
}

void Dop853::prepare_dense(const System& f) {
  const auto n = y0_.size();
  const double t = t_, h = h_;
  if (!hermite_ready_) prepare_hermite(f);
  k14_.resize(n);
  k15_.resize(n);
  k16_.resize(n);
  tmp_ = y0_ + h * (a141 * k1_ + a147 * k7_ + a148 * k8_ + a149 * k9_ + a1410 * k10_ +
                    a1411 * k11_ + a1412 * k12_ + a1413 * k13_);
  f(t + c14 * h, tmp_, k14_);
  tmp_ = y0_ + h * (a151 * k1_ + a156 * k6_ + a157 * k7_ + a158 * k8_ + a1511 * k11_ +
                    a1512 * k12_ + a1513 * k13_ + a1514 * k14_);
  f(t + c15 * h, tmp_, k15_);
  tmp_ = y0_ + h * (a161 * k1_ + a166 * k6_ + a167 * k7_ + a168 * k8_ + a169 * k9_ + a1613 * k13_ +
                    a1614 * k14_ + a1615 * k15_);
  f(t + c16 * h, tmp_, k16_);
  rhs_evals_ += 3;

  // cont(1..8) of dop853.f: r0..r3 from prepare_hermite, r4..r7 = h sum_i d_{k,i} k_i.
  r_[4] = h * (d41 * k1_ + d46 * k6_ + d47 * k7_ + d48 * k8_ + d49 * k9_ + d410 * k10_ +
               d411 * k11_ + d412 * k12_ + d413 * k13_ + d414 * k14_ + d415 * k15_ + d416 * k16_);
  r_[5] = h * (d51 * k1_ + d56 * k6_ + d57 * k7_ + d58 * k8_ + d59 * k9_ + d510 * k10_ +
               d511 * k11_ + d512 * k12_ + d513 * k13_ + d514 * k14_ + d515 * k15_ + d516 * k16_);
  r_[6] = h * (d61 * k1_ + d66 * k6_ + d67 * k7_ + d68 * k8_ + d69 * k9_ + d610 * k10_ +
               d611 * k11_ + d612 * k12_ + d613 * k13_ + d614 * k14_ + d615 * k15_ + d616 * k16_);
  r_[7] = h * (d71 * k1_ + d76 * k6_ + d77 * k7_ + d78 * k8_ + d79 * k9_ + d710 * k10_ +
               d711 * k11_ + d712 * k12_ + d713 * k13_ + d714 * k14_ + d715 * k15_ + d716 * k16_);
  dense_ready_ = true;
}

// contd8 of dop853.f, s = theta, s1 = 1 - s:
// y = r0 + s (r1 + s1 (r2 + s (r3 + s1 (r4 + s (r5 + s1 (r6 + s r7)))))).
void Dop853::dense(const System& f, double theta, Vec& out) {
  if (!dense_ready_) prepare_dense(f);
  const double s = theta, s1 = 1.0 - theta;
  out = r_[0] +
        s * (r_[1] +
             s1 * (r_[2] + s * (r_[3] + s1 * (r_[4] + s * (r_[5] + s1 * (r_[6] + s * r_[7]))))));
}

bool Dop853::cheap_interpolant(const System& f, double theta, Vec& out) {
  if (!hermite_ready_) prepare_hermite(f);
  const double s = theta, s1 = 1.0 - theta;
  out = r_[0] + s * (r_[1] + s1 * (r_[2] + s * r_[3]));
  return true;
}

// With s, 1 - s in [0, 1], each nested term of contd8 is at most the sum of the magnitudes
// inside it, so |y_i(theta) - r0_i| <= |r1_i| + ... + |r7_i| for every theta in [0, 1].
bool Dop853::dense_excursion(const System& f, Vec& e) {
  if (!dense_ready_) prepare_dense(f);
  e = r_[1].cwiseAbs();
  for (int k = 2; k < 8; ++k) e += r_[k].cwiseAbs();
  return true;
}

void Dop853::reset() { cache_.block(); }

}  // namespace ajx::numerics
