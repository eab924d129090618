test("answers ping", function()
  say("ping")
  expect.said("pong")
end)

test("a wrong expectation", function()
  say("ping")
  expect.said("PONG")
end)
