# Virtual material tests (cases/material_tests/) over the lattice angles 0, 10, 20, 30 degrees:
# each run must meet its own checks (analyse.py: energy balance within 1 %, a post-peak drop,
# quasi-static loading, the Brazilian crack on the loaded diameter within 2r) and the strength
# must lie within 5 % of its mean over the angles. The notched beam runs at r = 4 mm (its
# coarsest member) at angle 0: work of fracture and the drop of the load.
if(NOT HEXDEM_SANITIZE)
  foreach(kind tension compression brazilian)
    if(kind STREQUAL "brazilian")
      set(key split_strength_MPa)
    else()
      set(key peak_stress_MPa)
    endif()
    add_test(NAME case_material_${kind}_angles
      COMMAND ${HEXDEM_SYSTEM_PYTHON} ${PROJECT_SOURCE_DIR}/cases/material_tests/run_study.py ${kind}
              --angles 0,10,20,30 --out ${HEXDEM_TEST_WORK_DIR}/material_tests --jobs 2
              --hexdem $<TARGET_FILE:hexdem> --check ${key}=5)
    set_tests_properties(case_material_${kind}_angles PROPERTIES LABELS "validation" TIMEOUT 900
      ENVIRONMENT "PYTHONPATH=${HEXDEM_PYTHONPATH}")
  endforeach()
  add_test(NAME case_material_notched_beam
    COMMAND ${HEXDEM_SYSTEM_PYTHON} ${PROJECT_SOURCE_DIR}/cases/material_tests/run_study.py notched_beam
            --angles 0 --out ${HEXDEM_TEST_WORK_DIR}/material_tests --jobs 1 --hexdem $<TARGET_FILE:hexdem>)
  set_tests_properties(case_material_notched_beam PROPERTIES LABELS "validation" TIMEOUT 900
    ENVIRONMENT "PYTHONPATH=${HEXDEM_PYTHONPATH}")
endif()
