marvin.on("ping", function() marvin.say("pong") end)
