-- marvin.after on the host loop (tests/skills/sim_test.cpp): a timer due at once fires
-- before the next utterance is taken; one an hour away never fires on a stopped clock.
marvin.on("now", function()
  marvin.after(0, function() marvin.say("Ring!") end)
  marvin.say("Ringing soon.")
end)

marvin.on("later", function()
  marvin.after(3600, function() marvin.say("An hour passed.") end)
  marvin.say("Ringing in an hour.")
end)
