# CTest dashboard settings: `ctest -D Experimental` (or Nightly/Continuous) submits the module's test results to
# the CDash project named here, as ITK's remote modules do. Plain `ctest` runs the tests without submitting.
set(CTEST_PROJECT_NAME "FFDShapeMatching")
set(CTEST_NIGHTLY_START_TIME "01:00:00 UTC")
set(CTEST_DROP_METHOD "https")
set(CTEST_DROP_SITE "open.cdash.org")
set(CTEST_DROP_LOCATION "/submit.php?project=Insight")
set(CTEST_DROP_SITE_CDASH TRUE)
