# cases/narrow_plate (the paper's example 2) on a lattice of r = 1 mm, a quarter of the full
# case's disks: sigma_y along the plate at 104 us against 1D bar theory, and against an
# explicit CalculiX solution (1 mm elements) when ccx is installed (skipped otherwise).
add_test(NAME case_narrow_plate
  COMMAND ${HEXDEM_SYSTEM_PYTHON} ${PROJECT_SOURCE_DIR}/cases/narrow_plate/check.py
          $<TARGET_FILE:hexdem> ${HEXDEM_TEST_WORK_DIR}/case_narrow_plate)
set_tests_properties(case_narrow_plate PROPERTIES LABELS "validation" TIMEOUT 120)

add_test(NAME case_narrow_plate_calculix
  COMMAND ${HEXDEM_SYSTEM_PYTHON} ${PROJECT_SOURCE_DIR}/cases/narrow_plate/check.py
          $<TARGET_FILE:hexdem> ${HEXDEM_TEST_WORK_DIR}/case_narrow_plate_calculix --calculix)
set_tests_properties(case_narrow_plate_calculix PROPERTIES LABELS "validation" TIMEOUT 300
  SKIP_RETURN_CODE 77)
