-- Remembers one note in the skill's own storage.
marvin.on("remember", function(request)
  marvin.storage.set("note", request.slots.note)
  marvin.say("I will remember that.")
end)
