// SPDX-License-Identifier: MIT
// c4g-ident's rigid-body model in-process (CMocka): the base parameters of known arms
// (rigid_base.hpp), checked against their closed forms.
#include "rigid.hpp"
#include "rigid_base.hpp"

extern "C" {
#include "c4gh_ffmodel.h"
#include "c4gh_textfile.h"
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
}

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

using namespace ident;

namespace {

const double kDeg = M_PI / 180.0;

// The arm plant's kinematics (fixtures/ident/smart-six.kin), modified DH.
c4g_dyn_chain_t smart_six()
{
    const double a[6] = {0, 0.15, 0.59, 0.11, 0, 0};
    const double al[6] = {0, -90 * kDeg, 0, -90 * kDeg, 90 * kDeg, -90 * kDeg};
    const double d[6] = {0.45, 0, 0, 0.64, 0, 0};
    const double th[6] = {0, -90 * kDeg, 0, 0, 0, 0};
    const double g[3] = {0, 0, -9.81};
    c4g_dyn_chain_t ch;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, C4G_DYN_DH_MODIFIED, a, al, d, th, g), C4G_OK);
    return ch;
}

// A planar 2R arm in a vertical plane: both axes along the base z, gravity along -y,
// link 1 of length L1 (modified DH: a = 0, L1).
c4g_dyn_chain_t planar_2r(double L1)
{
    const double a[2] = {0, L1}, al[2] = {0, 0}, d[2] = {0, 0}, th[2] = {0, 0};
    const double g[3] = {0, -9.81, 0};
    c4g_dyn_chain_t ch;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 2, C4G_DYN_DH_MODIFIED, a, al, d, th, g), C4G_OK);
    return ch;
}

std::vector<std::string> names(const RigidBase &B)
{
    return B.name;
}

// The textbook set of the vertical 2R arm: link 1 turns about a fixed axis, so only its
// first moments (gravity) and Izz act; link 2's mass sits at the end of link 1 (a point mass
// m2 at distance L1 adds L1^2 m2 to Izz1 and L1 m2 to mx1); link 2 moves in the plane, so
// of its inertias only Izz2 acts; ia1 acts exactly as Izz1 does; ia2 alone. 7 in all
// (the 6 link combinations of the textbook plus one rotor).
void test_base_planar_2r(void **)
{
    RigidBase B;
    std::string err;
    assert_true(rigid_base(planar_2r(0.5), &B, &err));
    const std::vector<std::string> want = {"mx1 + 0.5*m2", "my1", "Izz1 + 0.25*m2 + ia1", "mx2", "my2", "Izz2", "ia2"};
    assert_int_equal(B.base.size(), want.size());
    for (std::size_t k = 0; k < want.size(); k++) assert_string_equal(names(B)[k].c_str(), want[k].c_str());
    assert_int_equal(B.rank_qr, 7);
    assert_int_equal(B.nfull, 22);
}

// The same arm in a horizontal plane (gravity along the axes): the first moments of link 1
// never act, those of link 2 still do through the inertia (mx2, my2 in the Coriolis and
// coupling terms), 5 in all.
void test_base_planar_2r_horizontal(void **)
{
    const double a[2] = {0, 0.5}, al[2] = {0, 0}, d[2] = {0, 0}, th[2] = {0, 0};
    const double g[3] = {0, 0, -9.81};
    c4g_dyn_chain_t ch;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 2, C4G_DYN_DH_MODIFIED, a, al, d, th, g), C4G_OK);
    RigidBase B;
    std::string err;
    assert_true(rigid_base(ch, &B, &err));
    const std::vector<std::string> want = {"Izz1 + 0.25*m2 + ia1", "mx2", "my2", "Izz2", "ia2"};
    assert_int_equal(B.base.size(), want.size());
    for (std::size_t k = 0; k < want.size(); k++) assert_string_equal(names(B)[k].c_str(), want[k].c_str());
}

// beta = P theta reproduces the torques of any full vector: W theta = W_b beta at fresh states.
void test_base_map_exact(void **)
{
    const c4g_dyn_chain_t ch = smart_six();
    RigidBase B;
    std::string err;
    assert_true(rigid_base(ch, &B, &err));
    Eigen::VectorXd theta = Eigen::VectorXd::Random(B.nfull);
    const Eigen::VectorXd beta = B.P * theta;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> W;
    for (int s = 0; s < 20; s++) {
        const Eigen::VectorXd q = Eigen::VectorXd::Random(6) * 3.0, qd = Eigen::VectorXd::Random(6) * 2.0,
                              qdd = Eigen::VectorXd::Random(6) * 7.0;
        assert_true(rigid_regressor(ch, q.data(), qd.data(), qdd.data(), &W));
        Eigen::MatrixXd Wb(6, static_cast<Eigen::Index>(B.base.size()));
        for (std::size_t k = 0; k < B.base.size(); k++) Wb.col(static_cast<Eigen::Index>(k)) = W.col(B.base[k]);
        const Eigen::VectorXd t1 = W * theta, t2 = Wb * beta;
        assert_true((t1 - t2).norm() <= 1e-9 * (1.0 + t1.norm()));
    }
}

// The arm plant: the literature's 36 base inertial parameters of a 6R arm with a spherical
// wrist (its shoulder and forearm offsets a2 = 0.15, a4 = 0.11 add none), and the rotors of
// axes 3..6: 40. ia1 acts exactly as Izz1 does (axis 1 fixed), ia2 exactly as Izz2 (axis 2
// is perpendicular to axis 1, so link 2's Izz adds to no other joint's torque and to no
// gyroscopic term): both are folded, so the count with rotors is 36 + 4, not 36 + 6.
// Stable against the sample count and the seed.
void test_base_smart_six(void **)
{
    const c4g_dyn_chain_t ch = smart_six();
    RigidBase B;
    std::string err;
    assert_true(rigid_base(ch, &B, &err));
    assert_string_equal(B.name[0].c_str(), "Izz1 + 0.0225*m2 + Iyy2 + 0.3706*m3 + Iyy3 + 0.3827*m4 + 0.3827*m5 + 0.3827*m6 + ia1");
    int rotors = 0;
    for (int b : B.base) rotors += (b >= 60) ? 1 : 0;
    assert_int_equal(rotors, 4);
    assert_int_equal(B.base.size(), 40);
    assert_int_equal(static_cast<int>(B.base.size()) - rotors, 36);
    for (unsigned seed : {2U, 3U}) {
        RigidBase C;
        assert_true(rigid_base(ch, &C, &err, 500, 1e-7, seed));
        assert_true(C.base == B.base);
        assert_true((C.K - B.K).cwiseAbs().maxCoeff() < 1e-6);
    }
}

void test_base_refused(void **)
{
    c4g_dyn_chain_t ch = smart_six();
    RigidBase B;
    std::string err;
    assert_false(rigid_base(ch, &B, &err, 10));
    assert_true(err.find("at least 11 samples") != std::string::npos);
    ch.n = 0;
    assert_false(rigid_base(ch, &B, &err));
}

// What the read-back of a rigid parameter file found: the kinematics through the kinematics
// file's own key handler (as the file's parser takes them), every other key by section.
struct ReadBack {
    c4gh_kinfile_t kf{};
    c4gh_kin_ctx_t kx{};
    std::map<std::string, std::map<std::string, std::string>> keys;
    const c4gh_tf_file_t *f = nullptr;
};

c4gh_tf_ini_rc_t on_key(void *user, const char *section, const char *name, const char *value, char *msg, size_t msglen)
{
    ReadBack *rb = static_cast<ReadBack *>(user);
    const int rc = c4gh_kin_on_key(&rb->kx, section, name, value, rb->f->line, msg, msglen);
    if (rc >= 0) return static_cast<c4gh_tf_ini_rc_t>(rc);
    rb->keys[section][name] = value;
    return C4GH_TF_INI_OK;
}

// The file the rigid fit writes, read back: checksum, kinematics verbatim, the full vector,
// ranges and friction exactly as written (17 digits: doubles round-trip).
void test_params_file_round_trip(void **)
{
    c4gh_kinfile_t kf;
    char err[512];
    assert_int_equal(c4gh_kin_load(FIXTURES_DIR "/ident/smart-six.kin", &kf, err, sizeof err), 0);
    RigidResult r;
    r.n = 6;
    r.arm = 1;
    r.period = 0.002;
    std::string why;
    assert_true(rigid_base(kf.chain, &r.base, &why));
    const std::size_t nb = r.base.base.size();
    r.theta.assign(static_cast<std::size_t>(r.base.nfull), 0.0);
    for (std::size_t k = 0; k < nb; k++) r.theta[static_cast<std::size_t>(r.base.base[k])] = 0.1 * static_cast<double>(k + 1) / 3.0;
    for (std::size_t k = 0; k < nb + 18; k++) {
        RigidParam p;
        p.value = (k < nb) ? r.theta[static_cast<std::size_t>(r.base.base[k])] : 1.0 / static_cast<double>(k + 7);
        r.params.push_back(p);
    }
    r.axes.resize(6);
    for (int j = 0; j < 6; j++) {
        r.q_min[j] = -0.5 - j / 7.0;
        r.q_max[j] = 0.25 + j / 9.0;
        r.qd_max[j] = 1.0 + j / 3.0;
        r.qdd_max[j] = 10.0 + j / 3.0;
        r.axes[static_cast<std::size_t>(j)].prep.eps = 0.03 + j / 1e3;
    }
    InputInfo in;
    in.path = "run.pcap";
    const std::string text = rigid_params_text(r, kf, {in}, "9.9.9");
    uint64_t sum = 0;
    assert_int_equal(c4gh_ffm_checksum_text(text.data(), text.size(), &sum), 0);
    char want[25];
    c4gh_ffm_checksum_format(sum, want);
    assert_non_null(std::strstr(text.c_str(), (std::string("checksum = ") + want + "\n").c_str()));
    ReadBack rb;
    c4gh_kin_begin(&rb.kx, &rb.kf, "kinematics");
    c4gh_tf_file_t f;
    c4gh_tf_open_mem(&f, "rigid.ini", text.data(), text.size());
    rb.f = &f;
    assert_int_equal(c4gh_tf_ini_parse(&f, on_key, &rb, err, sizeof err), 0);
    assert_int_equal(c4gh_kin_end(&rb.kx, "rigid.ini", err, sizeof err), 0);
    // the kinematics: what the kinematics file says, and the same chain
    assert_int_equal(rb.kf.n, 6);
    assert_int_equal(rb.kf.conv, C4G_DYN_DH_MODIFIED);
    assert_int_equal(rb.kf.deg, 1);
    assert_memory_equal(&rb.kf.chain, &kf.chain, sizeof kf.chain);
    for (int j = 0; j < 6; j++) assert_true(rb.kf.j[j].kt == kf.j[j].kt && rb.kf.j[j].alpha == kf.j[j].alpha);
    auto &model = rb.keys["model"];
    assert_string_equal(model["format"].c_str(), "c4g-ident 1");
    assert_string_equal(model["model"].c_str(), "rigid-body-1");
    assert_string_equal(model["range"].c_str(), "clamp");
    assert_string_equal(model["base_params"].c_str(), "40");
    assert_string_equal(model["source"].c_str(), "run.pcap");
    assert_string_equal(model["created_by"].c_str(), "c4g-ident 9.9.9");
    static const char *const pn[10] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
    for (int j = 0; j < 6; j++) {
        auto &J = rb.keys["joint " + std::to_string(j + 1)];
        for (int p = 0; p < 10; p++) assert_true(std::strtod(J[pn[p]].c_str(), nullptr) == r.theta[static_cast<std::size_t>(10 * j + p)]);
        assert_true(std::strtod(J["ia"].c_str(), nullptr) == r.theta[static_cast<std::size_t>(60 + j)]);
        assert_true(std::strtod(J["q_min"].c_str(), nullptr) == r.q_min[j]);
        assert_true(std::strtod(J["q_max"].c_str(), nullptr) == r.q_max[j]);
        assert_true(std::strtod(J["qd_max"].c_str(), nullptr) == r.qd_max[j]);
        assert_true(std::strtod(J["qdd_max"].c_str(), nullptr) == r.qdd_max[j]);
        auto &A = rb.keys["axis " + std::to_string(j + 1)];
        assert_true(std::strtod(A["Fv"].c_str(), nullptr) == r.params[nb + 3 * static_cast<std::size_t>(j)].value);
        assert_true(std::strtod(A["Fc"].c_str(), nullptr) == r.params[nb + 3 * static_cast<std::size_t>(j) + 1].value);
        assert_true(std::strtod(A["off"].c_str(), nullptr) == r.params[nb + 3 * static_cast<std::size_t>(j) + 2].value);
        assert_true(std::strtod(A["eps"].c_str(), nullptr) == r.axes[static_cast<std::size_t>(j)].prep.eps);
    }
    // and through the file's own parser (what c4g-server --ff reads), from disk
    char path[] = "/tmp/c4g-rigid-XXXXXX";
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
    assert_int_equal(close(fd), 0);
    c4gh_ffm_file_t ff;
    const int rc = c4gh_ffm_load(path, &ff, err, sizeof err);
    unlink(path);
    if (rc != 0) fail_msg("%s", err);
    assert_int_equal(ff.rigid, 1);
    assert_int_equal(ff.arm, 1);
    assert_true(ff.period_ms == 2.0);
    assert_int_equal(ff.checksum, sum);
    assert_int_equal(ff.consistent, 0);
    assert_int_equal(ff.base_params, 40);
    assert_int_equal(ff.kin.n, 6);
    assert_memory_equal(&ff.kin.chain, &kf.chain, sizeof kf.chain);
    for (int j = 0; j < 6; j++) {
        for (int p = 0; p < 10; p++) assert_true(ff.pi[10 * j + p] == r.theta[static_cast<std::size_t>(10 * j + p)]);
        assert_true(ff.ia[j] == r.theta[static_cast<std::size_t>(60 + j)]);
        assert_true(ff.q_min[j] == r.q_min[j] && ff.q_max[j] == r.q_max[j]);
        assert_true(ff.qd_max[j] == r.qd_max[j] && ff.qdd_max[j] == r.qdd_max[j]);
        assert_true(ff.kin.j[j].kt == kf.j[j].kt);
        const c4gh_ffm_axis_t &a = ff.ax[j];
        assert_int_equal(a.set, 1);
        assert_true(a.fv == r.params[nb + 3 * static_cast<std::size_t>(j)].value);
        assert_true(a.fc == r.params[nb + 3 * static_cast<std::size_t>(j) + 1].value);
        assert_true(a.off == r.params[nb + 3 * static_cast<std::size_t>(j) + 2].value);
        assert_true(a.eps == r.axes[static_cast<std::size_t>(j)].prep.eps);
    }
    // the torques of the file's full vector are those of the base solution: W theta = W_b beta
    // (the base members carry their combinations, the others are 0)
    Eigen::VectorXd th(66), beta(static_cast<Eigen::Index>(nb));
    for (int k = 0; k < 66; k++) th(k) = r.theta[static_cast<std::size_t>(k)];
    for (std::size_t k = 0; k < nb; k++) beta(static_cast<Eigen::Index>(k)) = r.params[k].value;
    assert_true((r.base.P * th - beta).norm() < 1e-12);
}

}  // namespace

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_base_planar_2r),
        cmocka_unit_test(test_base_planar_2r_horizontal),
        cmocka_unit_test(test_base_map_exact),
        cmocka_unit_test(test_base_smart_six),
        cmocka_unit_test(test_base_refused),
        cmocka_unit_test(test_params_file_round_trip),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
