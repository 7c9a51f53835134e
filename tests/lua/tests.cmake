# The Lua layer's tests run whole scenarios through the application's run
# (app/scenario_run.hpp): the sandbox and bindings are tested as a user meets them.
target_link_libraries(test_lua PRIVATE softcut_app)
