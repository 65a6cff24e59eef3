# The orthotropic half-plane (cases/halfplane/, paper Section 5.1 example 1) at r = 1 mm
# (18,000 disks): front speeds against theory, Lamb's problem against the continuum solution,
# and the refusal of the paper's shear model for material B. Bounds: cases/halfplane/README.md.
foreach(check fronts lamb rotation)
  add_test(NAME case_halfplane_${check}
    COMMAND ${HEXDEM_SYSTEM_PYTHON} ${PROJECT_SOURCE_DIR}/cases/halfplane/reduced.py
            $<TARGET_FILE:hexdem> ${HEXDEM_TEST_WORK_DIR}/case_halfplane_${check} ${check})
  set_tests_properties(case_halfplane_${check} PROPERTIES LABELS "validation" TIMEOUT 180)
endforeach()
