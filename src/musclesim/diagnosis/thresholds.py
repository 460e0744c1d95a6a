"""Every threshold of the sim-to-real diagnosis, in one place: what it decides and why its value.

Gaps and noise floors are normalised by each signal's measured range (0.01 = 1 % of the range).
A "noise floor" is a signal's estimated white-noise std
(`musclesim.diagnosis.stats.noise_estimate`), never below `NOISE_FLOOR`. The reports quoted in
the docs (the worked examples, §diagnosis; the dated results page) depend on these
values; changing one changes them. The evidence's levels are at the end.
"""

# -- where: does a unit deviate? ------------------------------------------------------------------
# A unit deviates when the held-out gap of one of its observed signals exceeds this many times that
# signal's own noise floor. Three standard deviations: white measurement noise alone stays below
# it, so a unit that matches its data within the noise is not blamed.
DEVIATES = 3.0

# The smallest noise floor, as a fraction of a signal's range. Noise-free or quantised data would
# otherwise give a floor of zero and call every numerical difference a deviation; 0.2 % of the
# range is below what a bench sensor resolves.
NOISE_FLOOR = 2e-3

# The relative noise floor of a scalar metric given without `uncertainty`: 2 % of its value (of the
# largest magnitude measured). A metric has no second differences to estimate its noise from, so
# a modest repeatability is assumed; a data set that knows better gives `uncertainty`.
METRIC_FLOOR = 0.02

# Samples of acquisition latency allowed for a sensor channel nothing in the model reads (a strain
# gauge logged by another device): the shift 0..MAX_ALIGN that fits the training part best is
# taken. A small number on purpose: a larger shift would start to absorb a real lag, which is an
# effect to diagnose (the library's thermocouple lag), not a nuisance.
MAX_ALIGN = 2

# -- calibration ----------------------------------------------------------------------------------
# Training values needed per calibration parameter: below it (a few scalar metrics) nothing is
# calibrated, since a fit of more nominal values than the data can pin would absorb any effect.
# Ten values per parameter is a common rule of thumb for a least-squares fit.
MIN_VALUES_PER_PARAMETER = 10

# -- each effect's fit, described (report ``effects``) ---------------------------------------------
# Each effect's fit is described against calibration alone on the signals it can change (the
# decision is the evidence's, below): it "gains clearly" when the gap there is material (one of
# those signals deviates, beyond DEVIATES times its noise), it shrinks it by at least this
# fraction (30 %) with a 95 % block-bootstrap interval above zero ...
MIN_SHRINKAGE = 0.3

# ... and its gain per held-out sample inside the regime it predicts (its signature) is at least
# this share of its gain per sample overall. Below 1 on purpose: effects acting through the
# hysteresis's memory spread their gain beyond the regime that triggers them.
SIGNATURE_MIN = 0.75

# -- is what is left explained? (``complete``) -----------------------------------------------------
# A gap left by the candidate the verdict names is unstructured when it is within STRUCTURED noise
# floors (the same three standard deviations as DEVIATES) ...
STRUCTURED = 3.0

# ... or at most this share (10 %) of the nominal gap: on clean data the noise floor can be far
# below a remaining gap that is still negligible next to what the candidate explained.
RESIDUAL_SHARE = 0.1

# -- fitting --------------------------------------------------------------------------------------
# Cost evaluations of one pass of a fit's trust-region least squares: STEPS per parameter, at
# least MAX_ITERATIONS. Each costs one run: the Jacobian is differenced at the pass's start (one
# run per parameter whose column is not known) and then carried along by Broyden's rank-one
# update from each accepted step (Dennis & Schnabel 1983, ch. 8), which learns it along the
# directions the steps explore; about n steps for n parameters, so two per parameter leave room
# for a trust region that shrinks on the way. Calibration and effects start near their optimum
# (the nominal or calibrated values, the best point of a scan), and the held-out gaps are
# reported to three digits: TOLERANCE is the relative change of the cost and of the box
# coordinates at which a pass ends, and the fall of the cost below which a step no longer counts
# as progress (PASSES).
STEPS = 2
MAX_ITERATIONS = 8
TOLERANCE = 1e-4
# Points of a periodic parameter's scan over one period (a PWM carrier's phase): the crawler
# bench's nominal gap over its carrier phase was one smooth well (§valves);
# one valve's under a jittery duty has side wells a few tenths of a period from the true one
# (tests/diagnosis/test_calibration.py): eighths start the local fit inside the true well.
PERIOD_POINTS = 8

# Candidates refitted with a fresh Jacobian: an effect is fitted first from the calibration's
# Jacobian columns (taken without the effect, so each fit costs a few runs), which can stop short
# of the joint optimum (a clamp's cold ends and the strain scale trade against each other); the
# two that fit the training part best, the ones the verdict turns on, are fitted again from
# there with every column fresh, as calibration alone was.
REFINED = 2

# Least-squares passes of a fit at most: the sensor channels' latencies (MAX_ALIGN) chosen again
# between passes and held within each (a latency switching inside a pass makes the residuals jump,
# and the trust region stalls next to the jump), and a pass from fresh differences after one that
# stopped short while its cost still fell (a trust region can collapse where an updated Jacobian is
# wrong; a fresh one shows whether the optimum is there). Each pass lowers the cost; two or three
# end it in practice (a lag trades at most MAX_ALIGN samples against the latency).
PASSES = 4

# -- statistics -----------------------------------------------------------------------------------
# Block-bootstrap resamples behind every 95 % interval: enough for stable 2.5 / 97.5 percentiles
# at the cost of cheap sums (no simulation is repeated).
BOOTSTRAP = 400

# Contiguous blocks per held-out part for the block bootstrap: blocks keep the residuals'
# autocorrelation within them; 20 blocks still give distinct resamples.
BLOCKS = 20

# The worst time windows (5 % of an experiment each) listed in the report's regimes section.
WINDOWS = 3

# -- evidence (musclesim.diagnosis.evidence) -------------------------------------------------------
# Highest order of a signal's autoregressive discrepancy, chosen below it by BIC on the calibrated
# model's training residuals: a slow mismatch with measurement noise on top (an AR(1) plus white
# noise, an ARMA(1, 1)) is approximated well by a few AR terms; more cost fits and gain nothing.
MAX_AR_ORDER = 5

# The credible set holds this share of the posterior probability: the candidates these data cannot
# tell apart, the smallest group that is wrong one time in ten at most.
CREDIBLE = 0.9

# Prior probability of a pair of causes, relative to a single cause (each single, calibration only
# included, equally probable): two unmodelled causes at once are rarer than one.
PAIR_PRIOR = 0.1

# The verdict names the most probable candidate when its probability reaches this, the credible
# set's level: exactly when the credible set holds it alone. Below it, the verdict is the set.
# (An effect whose signature the data hardly constrain stays near its prior odds, about even
# against calibration alone: named at even odds, it would be a coin toss.)
NAME_LEVEL = CREDIBLE

# Held-out predictive check: the RMS of a candidate's standardised held-out innovations (its
# discrepancy model's, estimated on the training part) is about 1 where the candidate and its
# discrepancy describe the data. Above this (a variance nine times the training part's) the data
# held out are not described: when no candidate passes, the verdict is `unexplained`.
PREDICTIVE_MAX = 3.0

# A symmetry, by either of two tests: the linear one (the effect's change at half its box that no
# recalibration reproduces, from the Fisher information), or a profile (the effect moved
# PROFILE_SCALE of its box each way from its fit, the calibration fitted again there) changes
# twice the log likelihood under the discrepancy by less than SYMMETRY_CHI2 (one noise variance
# over the training data): no fit to these data can tell the effect from a recalibration. A
# tenth of the box: near enough to the fit that the calibration's bounds leave room to follow it
# (a 2 K thermocouple offset against an ambient free by 8 K, fitted anywhere but its last 2 K); a
# quarter, tried first, left the ambient or the start temperature against a bound on our own
# bench, and the symmetry unfound.
PROFILE_SCALE = 0.1
SYMMETRY_CHI2 = 1.0


# -- the report's reading ----------------------------------------------------------------------
# A fitted value within this share of its range from a bound sits on its bound (report.json's
# `on_bound`, a warning each): the data would push it further, the range holds it, so the model's
# form, not the value, is what to question. 1 % of the range: a calibration's ranges are a few
# times a bench's spread, so a value this close is pressed there, not placed by chance. The
# decision stays where it was: the calibrated sets' own feature (`confidence.BOUND`) is tighter.
ON_BOUND = 0.01
